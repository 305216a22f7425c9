// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <array>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "core/io/raw_volume_format.h"
#include "core/volume/volume.h"

/// Sample decoding shared by the volume formats: what a header says about the data, and the
/// decoders of binary, ASCII and gzip data it describes.
namespace volspline::io::volume_data {

/// How the samples are stored.
enum class Encoding { Raw, Ascii, Gzip };

/// What a header says about where and how the samples are stored.
struct DataLayout {
  RawVolumeLayout raw;
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();
  Encoding encoding = Encoding::Raw;
  std::string data_file;          ///< empty: the data follows the header in the same bytes
  std::size_t data_offset = 0;    ///< attached data: offset of the first data byte
  long long byte_skip = 0;        ///< -1: the data is the last bytes of its file
  long long line_skip = 0;        ///< lines to skip in the data file before byte_skip
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();         ///< world position of voxel (0, 0, 0)
  Eigen::Matrix3d direction = Eigen::Matrix3d::Identity();  ///< column a: unit world direction of axis a
  double value_scale = 1;         ///< stored value v means value_scale * v + value_offset
  double value_offset = 0;
  bool round_values = false;      ///< round the scaled values (ASCII colour scalars in [0, 1] back to 0..255)
};

/// The sample type whose name in `names` (one per type, in the order UInt8, Int8, UInt16, Int16,
/// UInt32, Int32, Float32, Float64) is `key`. Throws volspline::Error
/// "name: unsupported sample type 'shown'" if none is.
volume::SampleType sample_type_named(const std::string& key, const std::array<const char*, 8>& names,
                                     const std::string& shown, const std::string& name);

/// Splits a world matrix whose column a is axis a's step (direction × spacing) into unit
/// directions and positive spacings. Throws volspline::Error naming `name` and `what` if a column
/// is zero or the columns are linearly dependent.
void set_axes_from_steps(DataLayout& layout, const Eigen::Matrix3d& steps, const std::string& name, const std::string& what);

/// nx * ny * nz; throws volspline::Error naming `name` if a size is not positive or the volume
/// has more than 2^31 voxels (checked before anything is allocated).
std::uint64_t checked_voxel_count(const std::array<int, 3>& dims, const std::string& name);

/// Throws volspline::Error "NAME: volume of XxYxZ voxels is above the limit `max_voxels` = N"
/// if nx * ny * nz exceeds max_voxels (the caller's documented limit, checked on the header).
void check_voxel_limit(const std::array<int, 3>& dims, std::int64_t max_voxels, const std::string& name);

/// Decodes binary samples from data[0, size); `exact` requires size to match, else extra bytes
/// are ignored. Throws volspline::Error naming `name` on truncated data or non-finite samples.
volume::Volume decode_binary(const char* data, std::size_t size, const RawVolumeLayout& layout,
                             const Eigen::Vector3d& spacing, bool exact, const std::string& name);

/// Decodes the data that starts at `begin` in `bytes` after applying the layout's skips and
/// encoding. Throws volspline::Error naming `name` on truncated, oversized or corrupt data.
volume::Volume decode_data(const std::string& bytes, std::size_t begin, const DataLayout& layout, const std::string& name);

}  // namespace volspline::io::volume_data
