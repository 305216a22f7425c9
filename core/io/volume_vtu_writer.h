// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/volume/frame_field.h"
#include "core/volume/volume.h"

namespace volspline::io {

/// Voxel hexes of a volume fit as VTK XML UnstructuredGrid (.vtu, ASCII): one point per voxel
/// centre at its world position (Volume::voxel_position), one VTK_HEXAHEDRON between each 2×2×2
/// block of voxel centres, PointData "density" (reconstruction), "sample" (the voxel's value), "error" (their difference)
/// and, when uvw has one row per voxel, "uvw". reconstruction: one value per voxel, x fastest
/// (asserted); uvw: num_voxels×3 parameters or empty.
std::string serialize_density_vtu(const volume::Volume& volume, const std::vector<double>& reconstruction,
                                  const Eigen::MatrixX3d& uvw);

/// Writes serialize_density_vtu atomically. Throws volspline::Error naming the path on failure.
void write_density_vtu(const std::string& path, const volume::Volume& volume,
                       const std::vector<double>& reconstruction, const Eigen::MatrixX3d& uvw);

/// A frame field as a .vtu of one VTK_VERTEX per voxel centre with the frame's three axes as
/// PointData vectors "f0", "f1", "f2" in world axes (glyph input). field: one frame per voxel
/// (asserted).
std::string serialize_frames_vtu(const volume::Volume& volume, const volume::FrameField& field);

/// Writes serialize_frames_vtu atomically. Throws volspline::Error naming the path on failure.
void write_frames_vtu(const std::string& path, const volume::Volume& volume, const volume::FrameField& field);

}  // namespace volspline::io
