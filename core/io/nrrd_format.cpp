// SPDX-License-Identifier: MIT
#include "core/io/nrrd_format.h"

#include <cstdint>
#include <vector>

#include "core/common/error.h"
#include "core/io/gzip_inflate.h"
#include "core/io/volume_header_text.h"

namespace volspline::io {

using namespace volume_text;
using volume_data::DataLayout;
using volume_data::Encoding;
using volume::SampleType;

namespace {

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

// "(a,b,c) (d,e,f)" with the brackets and commas as spaces.
std::string without_vector_marks(std::string text) {
  for (char& c : text)
    if (c == '(' || c == ')' || c == ',') c = ' ';
  return text;
}

}  // namespace

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
      // Each axis's world step "(a,b,c)": its length is the spacing, its direction the axis's
      // direction in the header's space (kept as written: LPS stays LPS, RAS stays RAS).
      const auto words = split_words(without_vector_marks(value));
      if (words.size() != 9) throw Error(name + ": space directions needs 3 vectors of 3 values");
      Eigen::Matrix3d steps;
      for (int a = 0; a < 3; ++a) {
        for (int k = 0; k < 3; ++k) steps(k, a) = parse_real(words[3 * a + k], name, "space directions");
        if (!(steps.col(a).norm() > 0)) throw Error(name + ": space direction " + std::to_string(a) + " has zero length");
      }
      volume_data::set_axes_from_steps(layout, steps, name, "space directions");
    } else if (field == "space origin") {
      const auto words = split_words(without_vector_marks(value));
      if (words.size() != 3) throw Error(name + ": space origin needs 3 values");
      for (int k = 0; k < 3; ++k) layout.origin[k] = parse_real(words[k], name, "space origin");
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

}  // namespace volspline::io
