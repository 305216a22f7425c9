// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace volspline::volume {

/// Sample type of a volume as stored in its file (the samples themselves are kept as float).
enum class SampleType { UInt8, Int8, UInt16, Int16, UInt32, Int32, Float32, Float64 };

/// Bytes per sample of `type` (1, 2, 4 or 8).
int sample_type_size(SampleType type);

/// Lower-case name of `type` as in file names: "uint8", "int16", "float32", ...
std::string sample_type_name(SampleType type);

/// A scalar volume image on a regular grid.
/// Voxel (x, y, z), 0 <= x < nx etc., sits at origin + direction * (x * spacing.x(), y * spacing.y(),
/// z * spacing.z()) in the file's world frame (voxel_position) and its sample is
/// samples[x + nx * (y + ny * z)] (x fastest). samples.size() == nx * ny * nz. The core works in
/// index × spacing coordinates; origin and direction place its outputs in the world.
struct Volume {
  int nx = 0;
  int ny = 0;
  int nz = 0;
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();  ///< voxel size along x, y, z (file units, > 0)
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();       ///< world position of voxel (0, 0, 0) (file units)
  Eigen::Matrix3d direction = Eigen::Matrix3d::Identity();  ///< column a: unit world direction of axis a
  std::vector<float> samples;
  SampleType original_type = SampleType::Float32;  ///< type in the file the samples came from

  /// Number of voxels nx * ny * nz.
  std::size_t num_voxels() const { return static_cast<std::size_t>(nx) * ny * nz; }
  /// True when origin is 0 and direction the identity (world = index × spacing).
  bool world_is_grid() const { return origin.isZero(0.0) && direction == Eigen::Matrix3d::Identity(); }
  /// World position origin + direction * p of p in index × spacing coordinates.
  Eigen::Vector3d world_from_grid(const Eigen::Vector3d& p) const { return origin + direction * p; }
  /// World position of voxel (x, y, z).
  Eigen::Vector3d voxel_position(int x, int y, int z) const {
    const Eigen::Vector3d p(x * spacing.x(), y * spacing.y(), z * spacing.z());
    return world_is_grid() ? p : world_from_grid(p);
  }
  /// Flat index of voxel (x, y, z); precondition: inside the grid.
  std::size_t index(int x, int y, int z) const {
    return static_cast<std::size_t>(x) + static_cast<std::size_t>(nx) * (static_cast<std::size_t>(y) + static_cast<std::size_t>(ny) * z);
  }
};

}  // namespace volspline::volume
