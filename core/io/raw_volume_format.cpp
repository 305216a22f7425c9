// SPDX-License-Identifier: MIT
#include "core/io/raw_volume_format.h"

#include <cstdlib>

#include "core/common/error.h"
#include "core/io/volume_data.h"
#include "core/io/volume_header_text.h"

namespace volspline::io {

using volume::SampleType;
using volume_text::lower;
using volume_text::split_words;

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

std::string raw_name_problem(const std::string& path) {
  const std::string need = "raw volume needs its dims and type (`raw_layout`), or a name like volume_64x64x64_uint8.raw";
  const auto slash = path.find_last_of("/\\");
  std::string stem = slash == std::string::npos ? path : path.substr(slash + 1);
  const auto dot = stem.find_last_of('.');
  if (dot != std::string::npos) stem = stem.substr(0, dot);
  const auto type_sep = stem.find_last_of('_');
  if (type_sep == std::string::npos) return need;
  const std::string type_text = lower(stem.substr(type_sep + 1));
  const auto dims_sep = type_sep == 0 ? std::string::npos : stem.find_last_of('_', type_sep - 1);
  const std::size_t dims_begin = dims_sep == std::string::npos ? 0 : dims_sep + 1;
  const std::string dims_text = stem.substr(dims_begin, type_sep - dims_begin);
  // Only a name of the _XxYxZ_TYPE form gets a message about its parts.
  bool dims_like = dims_text.find_first_of("xX") != std::string::npos;
  for (char c : dims_text) dims_like = dims_like && (std::isdigit(static_cast<unsigned char>(c)) || c == 'x' || c == 'X');
  if (!dims_like) return need;
  try {
    sample_type_from_name(type_text);
  } catch (const Error&) {
    return "the name's sample type '" + type_text +
           "' is not uint8, int8, uint16, int16, uint32, int32, float32 or float64 (give `raw_layout`, or a name like "
           "volume_64x64x64_uint8.raw)";
  }
  return "the name's dims '" + dims_text + "' are not three positive sizes XxYxZ of at most 9 digits (give " +
         "`raw_layout`, or a name like volume_64x64x64_uint8.raw)";
}

volume::Volume parse_raw_volume(const std::string& bytes, const RawVolumeLayout& layout, const std::string& name) {
  return volume_data::decode_binary(bytes.data(), bytes.size(), layout, Eigen::Vector3d::Ones(), true, name);
}

}  // namespace volspline::io
