// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace volspline::io {

/// Writer of VTK XML files (.vtu, .vti) with every data array in one appended raw-binary block
/// (`<AppendedData encoding="raw">`, header_type UInt64, little endian): each array compressed by
/// vtkZLibDataCompressor blocks of 32 KiB when the build has zlib (native builds), uncompressed
/// otherwise (the WebAssembly build has no zlib). Deterministic: the same arrays give the same
/// bytes. Usage: add the arrays (each call returns its `<DataArray .../>` element for the body),
/// then document(type, body).
class VtkXmlWriter {
 public:
  /// compress: zlib-compress the arrays if the build can (see compression_available).
  explicit VtkXmlWriter(bool compress = true);

  /// True if this build links zlib.
  static bool compression_available();
  /// True if this writer compresses.
  bool compressed() const { return compress_; }

  /// Adds an array of values.size()/components tuples; returns its DataArray element.
  /// extra_attributes (e.g. `RangeMin="0"`) are copied into the element. Precondition:
  /// components ≥ 1 and values.size() divisible by it.
  std::string add(const std::string& name, const std::vector<double>& values, int components = 1,
                  const std::string& extra_attributes = "");
  std::string add(const std::string& name, const std::vector<float>& values, int components = 1,
                  const std::string& extra_attributes = "");
  std::string add(const std::string& name, const std::vector<std::int64_t>& values, int components = 1,
                  const std::string& extra_attributes = "");
  std::string add(const std::string& name, const std::vector<std::int32_t>& values, int components = 1,
                  const std::string& extra_attributes = "");
  std::string add(const std::string& name, const std::vector<std::uint8_t>& values, int components = 1,
                  const std::string& extra_attributes = "");

  /// The file: XML declaration, `<VTKFile type="type" ...>`, `<type type_attributes>`, body,
  /// `</type>`, the appended block, `</VTKFile>`.
  std::string document(const std::string& type, const std::string& type_attributes, const std::string& body) const;

 private:
  std::string add_bytes(const std::string& vtk_type, const std::string& name, int components, const void* data,
                        std::size_t bytes, const std::string& extra_attributes);
  bool compress_ = false;
  std::string appended_;
};

}  // namespace volspline::io
