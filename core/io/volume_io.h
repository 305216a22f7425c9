// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <optional>
#include <string>

#include "core/volume/volume.h"

namespace volspline::io {

/// Volume file formats that volspline reads.
enum class VolumeFormat { Raw, Nrrd, Vtk, MetaImage };

/// Layout of a header-less raw volume: dims (x fastest), sample type, byte order.
struct RawVolumeLayout {
  std::array<int, 3> dims{0, 0, 0};
  volume::SampleType type = volume::SampleType::UInt8;
  bool big_endian = false;
};

/// Options of read_volume; only raw files use them.
struct VolumeReadOptions {
  std::optional<RawVolumeLayout> raw_layout;  ///< if unset, raw files need a name like fuel_64x64x64_uint8.raw
};

/// Format from a file name's extension: raw, nrrd/nhdr, vtk, mhd/mha.
/// Throws volspline::Error naming the path if the extension is unknown.
VolumeFormat volume_format_from_path(const std::string& path);

/// Sample type from its name: uint8, int8, uint16, int16, uint32, int32, float32, float64.
/// Throws volspline::Error naming the text if it is none of these.
volume::SampleType sample_type_from_name(const std::string& name);

/// Dims and type parsed from a file name ending in `_XxYxZ_TYPE.raw` (fuel_64x64x64_uint8.raw);
/// std::nullopt if the name does not have that form. Little-endian.
std::optional<RawVolumeLayout> raw_layout_from_name(const std::string& path);

/// Decodes a header-less raw volume held in memory. `name` is used in error messages.
/// Throws volspline::Error naming `name` if dims are not positive, the byte count differs from
/// dims * sample size, or a float sample is not finite.
volume::Volume parse_raw_volume(const std::string& bytes, const RawVolumeLayout& layout, const std::string& name);

/// Decodes an NRRD (attached data), legacy VTK STRUCTURED_POINTS (ASCII or BINARY) or MetaImage
/// .mha (ElementDataFile = LOCAL) held in memory. `name` is used in error messages.
/// Throws volspline::Error naming `name` and the problem on: bad magic, missing or bad header
/// fields, dimension other than 3, unsupported type or encoding ("gzip encoding not supported"),
/// detached data (use read_volume), truncated or oversized data, non-finite samples.
volume::Volume parse_volume(const std::string& bytes, VolumeFormat format, const std::string& name);

/// Reads a volume file; the format comes from the extension. NHDR and MetaImage .mhd headers may
/// name a detached data file, resolved relative to the header's folder. Raw files take their
/// layout from options.raw_layout or else from the file name.
/// Throws volspline::Error naming the file and the problem (see parse_volume, parse_raw_volume).
volume::Volume read_volume(const std::string& path, const VolumeReadOptions& options = {});

}  // namespace volspline::io
