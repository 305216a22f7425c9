// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/volume/frame_field.h"
#include "core/volume/volume.h"

namespace volspline::io {

/// A frame field as a .vtu of one VTK_VERTEX per voxel centre with the frame's three axes as
/// PointData vectors "f0", "f1", "f2" in world axes (glyph input); appended binary,
/// zlib-compressed where the build has zlib and `compress` is set (VtkXmlWriter). field: one
/// frame per voxel (asserted).
std::string serialize_frames_vtu(const volume::Volume& volume, const volume::FrameField& field,
                                 bool compress = true);

/// Writes serialize_frames_vtu atomically. Throws volspline::Error naming the path on failure.
void write_frames_vtu(const std::string& path, const volume::Volume& volume, const volume::FrameField& field);

}  // namespace volspline::io
