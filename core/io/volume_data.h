// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
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
};

/// nx * ny * nz; throws volspline::Error naming `name` if a size is not positive or the volume
/// has more than 2^31 voxels (checked before anything is allocated).
std::uint64_t checked_voxel_count(const std::array<int, 3>& dims, const std::string& name);

/// Decodes binary samples from data[0, size); `exact` requires size to match, else extra bytes
/// are ignored. Throws volspline::Error naming `name` on truncated data or non-finite samples.
volume::Volume decode_binary(const char* data, std::size_t size, const RawVolumeLayout& layout,
                             const Eigen::Vector3d& spacing, bool exact, const std::string& name);

/// Decodes the data that starts at `begin` in `bytes` after applying the layout's skips and
/// encoding. Throws volspline::Error naming `name` on truncated, oversized or corrupt data.
volume::Volume decode_data(const std::string& bytes, std::size_t begin, const DataLayout& layout, const std::string& name);

}  // namespace volspline::io::volume_data
