// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/spline/tspline.h"

namespace volspline::io {

/// GLB (binary glTF 2.0) preview of a geometric T-spline (dimension 3): one mesh with two
/// primitives, the boundary surface (the 6 domain faces sampled on a samples×samples lattice,
/// triangles, grey) and iso-parameter lines on it (`lines` lines per direction per face,
/// line segments, dark) in one scene. Float32 positions; the surface has unit vertex normals
/// (smooth shading in three.js and Blender). Asserts dimension 3, samples ≥ 2, lines ≥ 2.
std::string serialize_spline_glb(const spline::TSpline& spline, int samples = 33, int lines = 9);

/// Writes serialize_spline_glb atomically. Throws volspline::Error naming the path on failure.
void write_spline_glb(const std::string& path, const spline::TSpline& spline, int samples = 33,
                      int lines = 9);

}  // namespace volspline::io
