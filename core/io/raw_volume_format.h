// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <optional>
#include <string>

#include "core/volume/volume.h"

namespace volspline::io {

/// Layout of a header-less raw volume: dims (x fastest), sample type, byte order.
struct RawVolumeLayout {
  std::array<int, 3> dims{0, 0, 0};
  volume::SampleType type = volume::SampleType::UInt8;
  bool big_endian = false;
};

/// Sample type from its name: uint8, int8, uint16, int16, uint32, int32, float32, float64.
/// Throws volspline::Error naming the text if it is none of these.
volume::SampleType sample_type_from_name(const std::string& name);

/// Dims and type parsed from a file name ending in `_XxYxZ_TYPE.raw` (fuel_64x64x64_uint8.raw);
/// std::nullopt if the name does not have that form. Little-endian.
std::optional<RawVolumeLayout> raw_layout_from_name(const std::string& path);

/// Why raw_layout_from_name found no layout in the name: no `_XxYxZ_TYPE` part, an unknown
/// sample type ("uint7"), or dims that are not three positive sizes ("0x64x64").
std::string raw_name_problem(const std::string& path);

/// Decodes a header-less raw volume held in memory. `name` is used in error messages.
/// Throws volspline::Error naming `name` if dims are not positive, the byte count differs from
/// dims * sample size, or a float sample is not finite.
volume::Volume parse_raw_volume(const std::string& bytes, const RawVolumeLayout& layout, const std::string& name);

}  // namespace volspline::io
