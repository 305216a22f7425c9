// SPDX-License-Identifier: MIT
#include "core/io/vtk_xml_writer.h"

#include <cassert>
#include <cstring>

#include "core/common/error.h"

#ifdef VOLSPLINE_HAVE_ZLIB
#include <zlib.h>
#endif

namespace volspline::io {

namespace {

// VTK's default block size for compressed arrays.
constexpr std::size_t kBlockBytes = 32768;

void append_u64(std::string& out, std::uint64_t x) {
  for (int b = 0; b < 8; ++b) out += static_cast<char>((x >> (8 * b)) & 0xff);
}

}  // namespace

VtkXmlWriter::VtkXmlWriter(bool compress) : compress_(compress && compression_available()) {}

bool VtkXmlWriter::compression_available() {
#ifdef VOLSPLINE_HAVE_ZLIB
  return true;
#else
  return false;
#endif
}

std::string VtkXmlWriter::add_bytes(const std::string& vtk_type, const std::string& name, int components,
                                    const void* data, std::size_t bytes, const std::string& extra_attributes) {
  assert(components >= 1);
  const std::size_t offset = appended_.size();
  const auto* p = static_cast<const unsigned char*>(data);
  if (!compress_) {
    // Uncompressed: one UInt64 byte count, then the data.
    append_u64(appended_, bytes);
    appended_.append(reinterpret_cast<const char*>(p), bytes);
  } else {
#ifdef VOLSPLINE_HAVE_ZLIB
    // vtkZLibDataCompressor layout: [blocks, block size, last block size, compressed size of each
    // block], then the compressed blocks.
    const std::size_t blocks = bytes == 0 ? 0 : (bytes + kBlockBytes - 1) / kBlockBytes;
    const std::size_t last = blocks == 0 ? 0 : bytes - (blocks - 1) * kBlockBytes;
    std::vector<std::string> compressed(blocks);
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t size = b + 1 == blocks ? last : kBlockBytes;
      uLongf out_size = compressBound(static_cast<uLong>(size));
      compressed[b].resize(out_size);
      if (compress2(reinterpret_cast<Bytef*>(&compressed[b][0]), &out_size, p + b * kBlockBytes,
                    static_cast<uLong>(size), Z_DEFAULT_COMPRESSION) != Z_OK)
        throw Error("VTK XML writer: zlib compression failed");
      compressed[b].resize(out_size);
    }
    append_u64(appended_, blocks);
    append_u64(appended_, kBlockBytes);
    append_u64(appended_, last);
    for (const std::string& c : compressed) append_u64(appended_, c.size());
    for (const std::string& c : compressed) appended_ += c;
#endif
  }
  std::string element = "<DataArray type=\"" + vtk_type + "\" Name=\"" + name + "\"";
  if (components > 1) element += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  if (!extra_attributes.empty()) element += " " + extra_attributes;
  element += " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
  return element;
}

std::string VtkXmlWriter::add(const std::string& name, const std::vector<double>& values, int components,
                              const std::string& extra_attributes) {
  return add_bytes("Float64", name, components, values.data(), values.size() * sizeof(double), extra_attributes);
}
std::string VtkXmlWriter::add(const std::string& name, const std::vector<float>& values, int components,
                              const std::string& extra_attributes) {
  return add_bytes("Float32", name, components, values.data(), values.size() * sizeof(float), extra_attributes);
}
std::string VtkXmlWriter::add(const std::string& name, const std::vector<std::int64_t>& values, int components,
                              const std::string& extra_attributes) {
  return add_bytes("Int64", name, components, values.data(), values.size() * sizeof(std::int64_t), extra_attributes);
}
std::string VtkXmlWriter::add(const std::string& name, const std::vector<std::int32_t>& values, int components,
                              const std::string& extra_attributes) {
  return add_bytes("Int32", name, components, values.data(), values.size() * sizeof(std::int32_t), extra_attributes);
}
std::string VtkXmlWriter::add(const std::string& name, const std::vector<std::uint8_t>& values, int components,
                              const std::string& extra_attributes) {
  return add_bytes("UInt8", name, components, values.data(), values.size(), extra_attributes);
}

std::string VtkXmlWriter::document(const std::string& type, const std::string& type_attributes,
                                   const std::string& body) const {
  std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"" + type +
                    "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"";
  if (compress_) out += " compressor=\"vtkZLibDataCompressor\"";
  out += ">\n<" + type + (type_attributes.empty() ? "" : " " + type_attributes) + ">\n";
  out += body;
  out += "</" + type + ">\n<AppendedData encoding=\"raw\">\n_";
  out += appended_;
  out += "\n</AppendedData>\n</VTKFile>\n";
  return out;
}

}  // namespace volspline::io
