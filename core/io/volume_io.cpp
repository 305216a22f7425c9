// SPDX-License-Identifier: MIT
#include "core/io/volume_io.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <vector>

#include "core/common/error.h"
#include "core/io/file_bytes.h"
#include "core/io/gzip_inflate.h"

namespace volspline::io {

namespace {

using volume::SampleType;
using volume::Volume;

// Upper bound on the voxel count; the data size is checked against the file before allocating.
constexpr std::uint64_t kMaxVoxels = std::uint64_t{1} << 31;

enum class Encoding { Raw, Ascii, Gzip };

// What a header says about where and how the samples are stored.
struct DataLayout {
  RawVolumeLayout raw;
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();
  Encoding encoding = Encoding::Raw;
  std::string data_file;          // empty: the data follows the header in the same bytes
  std::size_t data_offset = 0;    // attached data: offset of the first data byte
  long long byte_skip = 0;        // -1: the data is the last bytes of its file
  long long line_skip = 0;        // lines to skip in the data file before byte_skip
};

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string trim(const std::string& text) {
  std::size_t begin = 0;
  std::size_t end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  return text.substr(begin, end - begin);
}

std::vector<std::string> split_words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  std::string word;
  while (in >> word) words.push_back(word);
  return words;
}

// Reads the line starting at pos (without '\n' or a trailing '\r') and moves pos past it.
// Returns false at end of input.
bool next_line(const std::string& bytes, std::size_t& pos, std::string& line) {
  if (pos >= bytes.size()) return false;
  const std::size_t end = bytes.find('\n', pos);
  const std::size_t stop = end == std::string::npos ? bytes.size() : end;
  line.assign(bytes, pos, stop - pos);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  pos = end == std::string::npos ? bytes.size() : end + 1;
  return true;
}

long long parse_integer(const std::string& text, const std::string& name, const std::string& what) {
  const std::string t = trim(text);
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(t.c_str(), &end, 10);
  if (t.empty() || *end != '\0' || errno == ERANGE) throw Error(name + ": bad " + what + " '" + t + "'");
  return value;
}

double parse_real(const std::string& text, const std::string& name, const std::string& what) {
  const std::string t = trim(text);
  char* end = nullptr;
  const double value = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0' || !std::isfinite(value)) throw Error(name + ": bad " + what + " '" + t + "'");
  return value;
}

std::array<int, 3> parse_dims(const std::vector<std::string>& words, const std::string& name, const std::string& what) {
  if (words.size() != 3) throw Error(name + ": " + what + " needs 3 values, got " + std::to_string(words.size()));
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) {
    const long long value = parse_integer(words[a], name, what);
    if (value < 1 || value > std::numeric_limits<int>::max())
      throw Error(name + ": " + what + " value " + words[a] + " is not a positive size");
    dims[a] = static_cast<int>(value);
  }
  return dims;
}

Eigen::Vector3d parse_spacing(const std::vector<std::string>& words, const std::string& name, const std::string& what) {
  if (words.size() != 3) throw Error(name + ": " + what + " needs 3 values, got " + std::to_string(words.size()));
  Eigen::Vector3d spacing;
  for (int a = 0; a < 3; ++a) {
    spacing[a] = parse_real(words[a], name, what);
    if (!(spacing[a] > 0)) throw Error(name + ": " + what + " value " + words[a] + " is not positive");
  }
  return spacing;
}

std::uint64_t checked_voxel_count(const std::array<int, 3>& dims, const std::string& name) {
  std::uint64_t count = 1;
  for (int d : dims) {
    if (d < 1) throw Error(name + ": volume dimensions must be positive, got " + std::to_string(d));
    count *= static_cast<std::uint64_t>(d);
    if (count > kMaxVoxels) throw Error(name + ": volume of " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]) + " voxels is too large");
  }
  return count;
}

bool host_is_big_endian() {
  const std::uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 0;
}

template <typename T>
float load_sample(const char* p, bool swap) {
  unsigned char buffer[sizeof(T)];
  std::memcpy(buffer, p, sizeof(T));
  if (swap)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(buffer[i], buffer[sizeof(T) - 1 - i]);
  T value;
  std::memcpy(&value, buffer, sizeof(T));
  return static_cast<float>(value);
}

float load(const char* p, SampleType type, bool swap) {
  switch (type) {
    case SampleType::UInt8: return load_sample<std::uint8_t>(p, false);
    case SampleType::Int8: return load_sample<std::int8_t>(p, false);
    case SampleType::UInt16: return load_sample<std::uint16_t>(p, swap);
    case SampleType::Int16: return load_sample<std::int16_t>(p, swap);
    case SampleType::UInt32: return load_sample<std::uint32_t>(p, swap);
    case SampleType::Int32: return load_sample<std::int32_t>(p, swap);
    case SampleType::Float32: return load_sample<float>(p, swap);
    case SampleType::Float64: return load_sample<double>(p, swap);
  }
  return 0.0f;
}

Volume make_volume(const RawVolumeLayout& layout, const Eigen::Vector3d& spacing) {
  Volume volume;
  volume.nx = layout.dims[0];
  volume.ny = layout.dims[1];
  volume.nz = layout.dims[2];
  volume.spacing = spacing;
  volume.original_type = layout.type;
  return volume;
}

void check_finite(const Volume& volume, const std::string& name) {
  for (std::size_t i = 0; i < volume.samples.size(); ++i)
    if (!std::isfinite(volume.samples[i]))
      throw Error(name + ": sample " + std::to_string(i) + " is not a finite number");
}

// Decodes binary samples from data[0, size); `exact` requires size to match, else extra bytes are ignored.
Volume decode_binary(const char* data, std::size_t size, const RawVolumeLayout& layout, const Eigen::Vector3d& spacing,
                     bool exact, const std::string& name) {
  const std::uint64_t count = checked_voxel_count(layout.dims, name);
  const std::uint64_t needed = count * static_cast<std::uint64_t>(volume::sample_type_size(layout.type));
  if (size < needed)
    throw Error(name + ": truncated data: expected " + std::to_string(needed) + " bytes, found " + std::to_string(size));
  if (exact && size != needed)
    throw Error(name + ": size mismatch: expected " + std::to_string(needed) + " bytes, found " + std::to_string(size));
  Volume volume = make_volume(layout, spacing);
  volume.samples.resize(count);
  const bool swap = layout.big_endian != host_is_big_endian();
  const int step = volume::sample_type_size(layout.type);
  for (std::uint64_t i = 0; i < count; ++i) volume.samples[i] = load(data + i * step, layout.type, swap);
  check_finite(volume, name);
  return volume;
}

Volume decode_ascii(const std::string& bytes, std::size_t begin, const RawVolumeLayout& layout,
                    const Eigen::Vector3d& spacing, const std::string& name) {
  const std::uint64_t count = checked_voxel_count(layout.dims, name);
  // Each value takes at least one character: reject impossible counts before allocating.
  if (begin > bytes.size() || bytes.size() - begin < count)
    throw Error(name + ": truncated data: expected " + std::to_string(count) + " values");
  Volume volume = make_volume(layout, spacing);
  volume.samples.resize(count);
  const char* p = bytes.c_str() + begin;
  for (std::uint64_t i = 0; i < count; ++i) {
    char* end = nullptr;
    const double value = std::strtod(p, &end);
    if (end == p)
      throw Error(name + ": truncated data: expected " + std::to_string(count) + " values, found " + std::to_string(i));
    if (!std::isfinite(value)) throw Error(name + ": sample " + std::to_string(i) + " is not a finite number");
    volume.samples[i] = static_cast<float>(value);
    p = end;
  }
  check_finite(volume, name);
  return volume;
}

SampleType nrrd_type(const std::string& text, const std::string& name) {
  const std::string t = lower(trim(text));
  if (t == "uchar" || t == "unsigned char" || t == "uint8" || t == "uint8_t") return SampleType::UInt8;
  if (t == "signed char" || t == "int8" || t == "int8_t") return SampleType::Int8;
  if (t == "ushort" || t == "unsigned short" || t == "unsigned short int" || t == "uint16" || t == "uint16_t")
    return SampleType::UInt16;
  if (t == "short" || t == "short int" || t == "signed short" || t == "signed short int" || t == "int16" ||
      t == "int16_t")
    return SampleType::Int16;
  if (t == "uint" || t == "unsigned int" || t == "uint32" || t == "uint32_t") return SampleType::UInt32;
  if (t == "int" || t == "signed int" || t == "int32" || t == "int32_t") return SampleType::Int32;
  if (t == "float") return SampleType::Float32;
  if (t == "double") return SampleType::Float64;
  throw Error(name + ": unsupported sample type '" + trim(text) + "'");
}

DataLayout parse_nrrd_header(const std::string& bytes, const std::string& name) {
  std::size_t pos = 0;
  std::string line;
  if (!next_line(bytes, pos, line) || line.rfind("NRRD000", 0) != 0) throw Error(name + ": not an NRRD file (missing NRRD000x magic)");
  DataLayout layout;
  bool has_type = false, has_sizes = false, has_dimension = false, has_encoding = false;
  bool attached_end = false;
  while (next_line(bytes, pos, line)) {
    if (line.empty()) {
      attached_end = true;
      break;
    }
    if (line[0] == '#') continue;
    if (line.find(":=") != std::string::npos) continue;  // key/value pairs carry no layout
    const std::size_t colon = line.find(": ");
    if (colon == std::string::npos) throw Error(name + ": bad NRRD header line '" + line + "'");
    const std::string field = lower(trim(line.substr(0, colon)));
    const std::string value = trim(line.substr(colon + 2));
    if (field == "type") {
      layout.raw.type = nrrd_type(value, name);
      has_type = true;
    } else if (field == "dimension") {
      const long long dimension = parse_integer(value, name, "dimension");
      if (dimension != 3) throw Error(name + ": only 3-dimensional NRRD volumes are supported, got dimension " + value);
      has_dimension = true;
    } else if (field == "sizes") {
      layout.raw.dims = parse_dims(split_words(value), name, "sizes");
      has_sizes = true;
    } else if (field == "endian") {
      const std::string endian = lower(value);
      if (endian != "little" && endian != "big") throw Error(name + ": bad endian '" + value + "'");
      layout.raw.big_endian = endian == "big";
    } else if (field == "encoding") {
      const std::string encoding = lower(value);
      if (encoding == "raw") {
        layout.encoding = Encoding::Raw;
      } else if (encoding == "ascii" || encoding == "text" || encoding == "txt") {
        layout.encoding = Encoding::Ascii;
      } else if (encoding == "gzip" || encoding == "gz") {
        if (!gzip_available()) throw Error(name + ": gzip encoding not supported (volspline is built without zlib)");
        layout.encoding = Encoding::Gzip;
      } else {
        throw Error(name + ": unsupported encoding '" + value + "'");
      }
      has_encoding = true;
    } else if (field == "data file" || field == "datafile") {
      if (value.rfind("LIST", 0) == 0 || value.find('%') != std::string::npos)
        throw Error(name + ": multi-file data ('" + value + "') is not supported");
      layout.data_file = value;
    } else if (field == "spacings") {
      layout.spacing = parse_spacing(split_words(value), name, "spacings");
    } else if (field == "space directions") {
      // Axis spacing is the length of each direction vector "(a,b,c)".
      std::string cleaned = value;
      for (char& c : cleaned)
        if (c == '(' || c == ')' || c == ',') c = ' ';
      const auto words = split_words(cleaned);
      if (words.size() != 9) throw Error(name + ": space directions needs 3 vectors of 3 values");
      for (int a = 0; a < 3; ++a) {
        Eigen::Vector3d direction;
        for (int k = 0; k < 3; ++k) direction[k] = parse_real(words[3 * a + k], name, "space directions");
        if (!(direction.norm() > 0)) throw Error(name + ": space direction " + std::to_string(a) + " has zero length");
        layout.spacing[a] = direction.norm();
      }
    } else if (field == "byte skip") {
      layout.byte_skip = parse_integer(value, name, "byte skip");
      if (layout.byte_skip < -1) throw Error(name + ": bad byte skip " + value);
    } else if (field == "line skip") {
      layout.line_skip = parse_integer(value, name, "line skip");
      if (layout.line_skip < 0) throw Error(name + ": bad line skip " + value);
    }
  }
  if (!has_type) throw Error(name + ": NRRD header has no type");
  if (!has_dimension) throw Error(name + ": NRRD header has no dimension");
  if (!has_sizes) throw Error(name + ": NRRD header has no sizes");
  if (!has_encoding) throw Error(name + ": NRRD header has no encoding");
  if (layout.data_file.empty() && !attached_end) throw Error(name + ": NRRD header ends without a blank line before the data");
  if (layout.byte_skip == -1 && layout.encoding != Encoding::Raw)
    throw Error(name + ": byte skip -1 needs raw encoding");
  layout.data_offset = pos;
  return layout;
}

SampleType vtk_type(const std::string& text, const std::string& name) {
  const std::string t = lower(text);
  if (t == "unsigned_char") return SampleType::UInt8;
  if (t == "char") return SampleType::Int8;
  if (t == "unsigned_short") return SampleType::UInt16;
  if (t == "short") return SampleType::Int16;
  if (t == "unsigned_int") return SampleType::UInt32;
  if (t == "int") return SampleType::Int32;
  if (t == "float") return SampleType::Float32;
  if (t == "double") return SampleType::Float64;
  throw Error(name + ": unsupported sample type '" + text + "'");
}

DataLayout parse_vtk_header(const std::string& bytes, const std::string& name) {
  std::size_t pos = 0;
  std::string line;
  if (!next_line(bytes, pos, line) || line.rfind("# vtk DataFile", 0) != 0)
    throw Error(name + ": not a legacy VTK file (missing '# vtk DataFile' line)");
  if (!next_line(bytes, pos, line)) throw Error(name + ": truncated VTK header (no title line)");
  if (!next_line(bytes, pos, line)) throw Error(name + ": truncated VTK header (no ASCII/BINARY line)");
  DataLayout layout;
  const std::string mode = lower(trim(line));
  if (mode == "ascii") {
    layout.encoding = Encoding::Ascii;
  } else if (mode == "binary") {
    layout.encoding = Encoding::Raw;
    layout.raw.big_endian = true;  // legacy VTK binary data is big-endian
  } else {
    throw Error(name + ": expected ASCII or BINARY, got '" + trim(line) + "'");
  }
  bool has_dataset = false, has_dims = false, has_scalars = false;
  long long point_count = -1;
  while (next_line(bytes, pos, line)) {
    const auto words = split_words(line);
    if (words.empty()) continue;
    const std::string keyword = lower(words[0]);
    const std::vector<std::string> args(words.begin() + 1, words.end());
    if (keyword == "dataset") {
      if (args.size() != 1 || lower(args[0]) != "structured_points")
        throw Error(name + ": only DATASET STRUCTURED_POINTS is supported, got '" + trim(line) + "'");
      has_dataset = true;
    } else if (!has_dataset) {
      throw Error(name + ": expected DATASET STRUCTURED_POINTS, got '" + trim(line) + "'");
    } else if (keyword == "dimensions") {
      layout.raw.dims = parse_dims(args, name, "DIMENSIONS");
      has_dims = true;
    } else if (keyword == "spacing" || keyword == "aspect_ratio") {
      layout.spacing = parse_spacing(args, name, "SPACING");
    } else if (keyword == "origin") {
      continue;  // the origin does not affect samples or derivatives
    } else if (keyword == "point_data") {
      if (args.size() != 1) throw Error(name + ": bad POINT_DATA line '" + trim(line) + "'");
      point_count = parse_integer(args[0], name, "POINT_DATA count");
    } else if (keyword == "scalars") {
      if (point_count < 0) throw Error(name + ": SCALARS before POINT_DATA");
      if (args.size() < 2 || args.size() > 3) throw Error(name + ": bad SCALARS line '" + trim(line) + "'");
      layout.raw.type = vtk_type(args[1], name);
      if (args.size() == 3 && parse_integer(args[2], name, "SCALARS component count") != 1)
        throw Error(name + ": only 1-component SCALARS are supported");
      has_scalars = true;
    } else if (keyword == "lookup_table") {
      if (!has_scalars) throw Error(name + ": LOOKUP_TABLE before SCALARS");
      break;
    } else if (keyword == "cell_data" || keyword == "field" || keyword == "vectors" || keyword == "tensors") {
      throw Error(name + ": unsupported VTK section '" + words[0] + "' (only point SCALARS are read)");
    } else {
      throw Error(name + ": unknown VTK keyword '" + words[0] + "'");
    }
  }
  if (!has_dims) throw Error(name + ": VTK header has no DIMENSIONS");
  if (!has_scalars) throw Error(name + ": VTK header has no SCALARS with LOOKUP_TABLE");
  const std::uint64_t count = checked_voxel_count(layout.raw.dims, name);
  if (static_cast<std::uint64_t>(point_count) != count)
    throw Error(name + ": POINT_DATA " + std::to_string(point_count) + " does not match DIMENSIONS (" + std::to_string(count) + " points)");
  layout.data_offset = pos;
  return layout;
}

SampleType met_type(const std::string& text, const std::string& name) {
  const std::string t = trim(text);
  if (t == "MET_UCHAR") return SampleType::UInt8;
  if (t == "MET_CHAR") return SampleType::Int8;
  if (t == "MET_USHORT") return SampleType::UInt16;
  if (t == "MET_SHORT") return SampleType::Int16;
  if (t == "MET_UINT") return SampleType::UInt32;
  if (t == "MET_INT") return SampleType::Int32;
  if (t == "MET_FLOAT") return SampleType::Float32;
  if (t == "MET_DOUBLE") return SampleType::Float64;
  throw Error(name + ": unsupported sample type '" + t + "'");
}

bool met_bool(const std::string& text, const std::string& name, const std::string& key) {
  const std::string t = lower(trim(text));
  if (t == "true" || t == "1") return true;
  if (t == "false" || t == "0") return false;
  throw Error(name + ": bad " + key + " '" + trim(text) + "'");
}

DataLayout parse_metaimage_header(const std::string& bytes, const std::string& name) {
  DataLayout layout;
  std::size_t pos = 0;
  std::string line;
  bool has_dims = false, has_type = false, has_data_file = false, has_ndims = false;
  while (next_line(bytes, pos, line)) {
    if (trim(line).empty()) continue;
    const std::size_t equals = line.find('=');
    if (equals == std::string::npos) throw Error(name + ": bad MetaImage header line '" + line + "'");
    const std::string key = trim(line.substr(0, equals));
    const std::string value = trim(line.substr(equals + 1));
    if (key == "NDims") {
      if (parse_integer(value, name, "NDims") != 3) throw Error(name + ": only 3-dimensional MetaImage volumes are supported, got NDims " + value);
      has_ndims = true;
    } else if (key == "DimSize") {
      layout.raw.dims = parse_dims(split_words(value), name, "DimSize");
      has_dims = true;
    } else if (key == "ElementType") {
      layout.raw.type = met_type(value, name);
      has_type = true;
    } else if (key == "ElementSpacing" || (key == "ElementSize" && layout.spacing == Eigen::Vector3d::Ones())) {
      layout.spacing = parse_spacing(split_words(value), name, key);
    } else if (key == "ElementByteOrderMSB" || key == "BinaryDataByteOrderMSB") {
      layout.raw.big_endian = met_bool(value, name, key);
    } else if (key == "BinaryData") {
      if (!met_bool(value, name, key)) throw Error(name + ": ASCII MetaImage data is not supported");
    } else if (key == "CompressedData") {
      if (met_bool(value, name, key)) throw Error(name + ": compressed MetaImage data is not supported");
    } else if (key == "ElementNumberOfChannels") {
      if (parse_integer(value, name, key) != 1) throw Error(name + ": only 1-channel MetaImage volumes are supported");
    } else if (key == "HeaderSize") {
      layout.byte_skip = parse_integer(value, name, key);
      if (layout.byte_skip < -1) throw Error(name + ": bad HeaderSize " + value);
    } else if (key == "ElementDataFile") {
      if (value == "LIST" || value.find('%') != std::string::npos)
        throw Error(name + ": multi-file data ('" + value + "') is not supported");
      if (value != "LOCAL") layout.data_file = value;
      has_data_file = true;
      break;  // ElementDataFile is the last header field; LOCAL data follows
    }
  }
  if (!has_ndims) throw Error(name + ": MetaImage header has no NDims");
  if (!has_dims) throw Error(name + ": MetaImage header has no DimSize");
  if (!has_type) throw Error(name + ": MetaImage header has no ElementType");
  if (!has_data_file) throw Error(name + ": MetaImage header has no ElementDataFile");
  layout.data_offset = pos;
  return layout;
}

DataLayout parse_header(const std::string& bytes, VolumeFormat format, const std::string& name) {
  switch (format) {
    case VolumeFormat::Nrrd: return parse_nrrd_header(bytes, name);
    case VolumeFormat::Vtk: return parse_vtk_header(bytes, name);
    case VolumeFormat::MetaImage: return parse_metaimage_header(bytes, name);
    case VolumeFormat::Raw: break;
  }
  throw Error(name + ": raw volumes need dims and type (use parse_raw_volume)");
}

// Decodes the data that starts at `begin` in `bytes` after applying the header's skips.
Volume decode_data(const std::string& bytes, std::size_t begin, const DataLayout& layout, const std::string& name) {
  std::size_t pos = begin;
  std::string line;
  for (long long i = 0; i < layout.line_skip; ++i)
    if (!next_line(bytes, pos, line)) throw Error(name + ": truncated data: cannot skip " + std::to_string(layout.line_skip) + " lines");
  if (layout.encoding == Encoding::Ascii) return decode_ascii(bytes, pos, layout.raw, layout.spacing, name);
  if (layout.encoding == Encoding::Gzip) {
    // NRRD: the byte skip of compressed data counts decompressed bytes (before the samples).
    const std::uint64_t count = checked_voxel_count(layout.raw.dims, name);
    const std::uint64_t needed = count * static_cast<std::uint64_t>(volume::sample_type_size(layout.raw.type)) +
                                 static_cast<std::uint64_t>(layout.byte_skip);
    const std::string plain = gzip_inflate(bytes.data() + pos, bytes.size() - pos, static_cast<std::size_t>(needed), name);
    const std::size_t skip = static_cast<std::size_t>(layout.byte_skip);
    return decode_binary(plain.data() + skip, plain.size() - skip, layout.raw, layout.spacing, false, name);
  }
  if (layout.byte_skip == -1) {
    const std::uint64_t count = checked_voxel_count(layout.raw.dims, name);
    const std::uint64_t needed = count * static_cast<std::uint64_t>(volume::sample_type_size(layout.raw.type));
    if (bytes.size() - pos < needed)
      throw Error(name + ": truncated data: expected " + std::to_string(needed) + " bytes, found " + std::to_string(bytes.size() - pos));
    pos = bytes.size() - static_cast<std::size_t>(needed);
  } else {
    if (static_cast<std::uint64_t>(layout.byte_skip) > bytes.size() - pos)
      throw Error(name + ": truncated data: byte skip " + std::to_string(layout.byte_skip) + " is past the end");
    pos += static_cast<std::size_t>(layout.byte_skip);
  }
  return decode_binary(bytes.data() + pos, bytes.size() - pos, layout.raw, layout.spacing, false, name);
}

std::string sibling_path(const std::string& header_path, const std::string& file) {
  if (!file.empty() && file[0] == '/') return file;
  const auto slash = header_path.find_last_of("/\\");
  if (slash == std::string::npos) return file;
  return header_path.substr(0, slash + 1) + file;
}

}  // namespace

VolumeFormat volume_format_from_path(const std::string& path) {
  const std::string ext = file_extension(path);
  if (ext == "raw") return VolumeFormat::Raw;
  if (ext == "nrrd" || ext == "nhdr") return VolumeFormat::Nrrd;
  if (ext == "vtk") return VolumeFormat::Vtk;
  if (ext == "mhd" || ext == "mha") return VolumeFormat::MetaImage;
  throw Error(path + ": unknown volume file extension '" + ext + "'");
}

volume::SampleType sample_type_from_name(const std::string& name) {
  for (SampleType type : {SampleType::UInt8, SampleType::Int8, SampleType::UInt16, SampleType::Int16, SampleType::UInt32,
                          SampleType::Int32, SampleType::Float32, SampleType::Float64})
    if (volume::sample_type_name(type) == name) return type;
  throw Error("unknown sample type '" + name + "' (expected uint8, int8, uint16, int16, uint32, int32, float32 or float64)");
}

std::optional<RawVolumeLayout> raw_layout_from_name(const std::string& path) {
  const auto slash = path.find_last_of("/\\");
  std::string stem = slash == std::string::npos ? path : path.substr(slash + 1);
  const auto dot = stem.find_last_of('.');
  if (dot != std::string::npos) stem = stem.substr(0, dot);
  const auto type_sep = stem.find_last_of('_');
  if (type_sep == std::string::npos) return std::nullopt;
  const auto dims_sep = stem.find_last_of('_', type_sep == 0 ? 0 : type_sep - 1);
  const std::string dims_text = stem.substr(dims_sep == std::string::npos ? 0 : dims_sep + 1,
                                            type_sep - (dims_sep == std::string::npos ? 0 : dims_sep + 1));
  const std::string type_text = lower(stem.substr(type_sep + 1));
  RawVolumeLayout layout;
  try {
    layout.type = sample_type_from_name(type_text);
  } catch (const Error&) {
    return std::nullopt;
  }
  std::string cleaned = dims_text;
  for (char& c : cleaned) {
    if (c == 'x' || c == 'X') c = ' ';
    else if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
  }
  const auto words = split_words(cleaned);
  if (words.size() != 3) return std::nullopt;
  for (int a = 0; a < 3; ++a) {
    if (words[a].size() > 9) return std::nullopt;
    layout.dims[a] = std::atoi(words[a].c_str());
    if (layout.dims[a] < 1) return std::nullopt;
  }
  return layout;
}

volume::Volume parse_raw_volume(const std::string& bytes, const RawVolumeLayout& layout, const std::string& name) {
  return decode_binary(bytes.data(), bytes.size(), layout, Eigen::Vector3d::Ones(), true, name);
}

volume::Volume parse_volume(const std::string& bytes, VolumeFormat format, const std::string& name) {
  const DataLayout layout = parse_header(bytes, format, name);
  if (!layout.data_file.empty())
    throw Error(name + ": data is in the detached file '" + layout.data_file + "'; read it with read_volume");
  return decode_data(bytes, layout.data_offset, layout, name);
}

volume::Volume read_volume(const std::string& path, const VolumeReadOptions& options) {
  const VolumeFormat format = volume_format_from_path(path);
  if (format == VolumeFormat::Raw) {
    std::optional<RawVolumeLayout> layout = options.raw_layout;
    if (!layout) layout = raw_layout_from_name(path);
    if (!layout)
      throw Error(path + ": raw volume needs --dims X,Y,Z and --type, or a name like volume_64x64x64_uint8.raw");
    return parse_raw_volume(read_file_bytes(path), *layout, path);
  }
  const std::string bytes = read_file_bytes(path);
  const DataLayout layout = parse_header(bytes, format, path);
  if (layout.data_file.empty()) return decode_data(bytes, layout.data_offset, layout, path);
  const std::string data_path = sibling_path(path, layout.data_file);
  return decode_data(read_file_bytes(data_path), 0, layout, data_path);
}

}  // namespace volspline::io
