// SPDX-License-Identifier: MIT
#include "core/io/metaimage_format.h"

#include <cstdint>
#include <vector>

#include "core/common/error.h"
#include "core/io/volume_header_text.h"

namespace volspline::io {

using namespace volume_text;
using volume_data::DataLayout;
using volume_data::Encoding;
using volume::SampleType;

namespace {

SampleType met_type(const std::string& text, const std::string& name) {
  const std::string t = trim(text);
  return volume_data::sample_type_named(
      t, {"MET_UCHAR", "MET_CHAR", "MET_USHORT", "MET_SHORT", "MET_UINT", "MET_INT", "MET_FLOAT", "MET_DOUBLE"}, t, name);
}

bool met_bool(const std::string& text, const std::string& name, const std::string& key) {
  const std::string t = lower(trim(text));
  if (t == "true" || t == "1") return true;
  if (t == "false" || t == "0") return false;
  throw Error(name + ": bad " + key + " '" + trim(text) + "'");
}

}  // namespace

DataLayout parse_metaimage_header(const std::string& bytes, const std::string& name) {
  DataLayout layout;
  std::size_t pos = 0;
  std::string line;
  bool has_dims = false, has_type = false, has_data_file = false, has_ndims = false;
  Eigen::Matrix3d direction = Eigen::Matrix3d::Identity();
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
      // zlib data (VTK's and ITK's default .zraw); its size follows from DimSize and ElementType.
      if (met_bool(value, name, key)) layout.encoding = Encoding::Gzip;
    } else if (key == "Offset" || key == "Position" || key == "Origin") {
      const auto words = split_words(value);
      if (words.size() != 3) throw Error(name + ": " + key + " needs 3 values, got " + std::to_string(words.size()));
      for (int k = 0; k < 3; ++k) layout.origin[k] = parse_real(words[k], name, key);
    } else if (key == "TransformMatrix" || key == "Rotation" || key == "Orientation") {
      // MetaIO lists axis a's direction as values 3a..3a+2 (ITK's MetaImageIO writes them so).
      const auto words = split_words(value);
      if (words.size() != 9) throw Error(name + ": " + key + " needs 9 values, got " + std::to_string(words.size()));
      for (int a = 0; a < 3; ++a)
        for (int k = 0; k < 3; ++k) direction(k, a) = parse_real(words[3 * a + k], name, key);
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
  volume_data::set_axes_from_steps(layout, direction * layout.spacing.asDiagonal(), name, "TransformMatrix");
  if (!has_dims) throw Error(name + ": MetaImage header has no DimSize");
  if (!has_type) throw Error(name + ": MetaImage header has no ElementType");
  if (!has_data_file) throw Error(name + ": MetaImage header has no ElementDataFile");
  if (layout.encoding == Encoding::Gzip && layout.byte_skip != 0)
    throw Error(name + ": HeaderSize with CompressedData is not supported");
  layout.data_offset = pos;
  return layout;
}

}  // namespace volspline::io
