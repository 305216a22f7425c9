// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/volume/volume.h"

namespace volspline::io {

/// The voxels of a volume fit as VTK XML ImageData (.vti): WholeExtent, Origin, Spacing and
/// Direction place voxel (x, y, z) where Volume::voxel_position does; PointData "sample" (the
/// voxel's value, the active scalars), "density" (reconstruction), "error" (density − sample)
/// and, when uvw has one row per voxel, "uvw". Appended binary, zlib-compressed where the build
/// has zlib (VtkXmlWriter). reconstruction: one value per voxel, x fastest (asserted).
std::string serialize_density_vti(const volume::Volume& volume, const std::vector<double>& reconstruction,
                                  const Eigen::MatrixX3d& uvw, bool compress = true);

/// Writes serialize_density_vti atomically. Throws volspline::Error naming the path on failure.
void write_density_vti(const std::string& path, const volume::Volume& volume,
                       const std::vector<double>& reconstruction, const Eigen::MatrixX3d& uvw);

}  // namespace volspline::io
