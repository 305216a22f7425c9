// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <vector>

#include "core/spline/gpc_spline.h"

namespace volspline::spline {

/// The boundary surface of a geometric GPC spline (dimension 3), every point tagged with its
/// cuboid, and iso-parameter lines on it, as flat arrays (the browser's view reads them as they are).
struct GpcBoundaryTessellation {
  std::vector<float> surface_xyz;                ///< samples² points per Surface face, 3 floats each, model units
  std::vector<float> surface_uvw;                ///< their parameters as fractions of their cuboid's box, [0, 1]³
  std::vector<std::uint32_t> surface_cuboid;     ///< the cuboid of each point
  std::vector<std::uint32_t> surface_triangles;  ///< 3 point ids per triangle, out of the solid
  std::vector<float> line_xyz;                   ///< line segments, 2 points (6 floats) each
  std::vector<float> line_uvw;                   ///< their parameters as fractions of their cuboid's box
  std::vector<std::uint32_t> line_cuboid;        ///< the cuboid of each segment
};

/// Samples every face of every cuboid that lies on the solid's surface (GpcFaceJoin::Surface; a
/// glued face is inside the solid) like tessellate_boundary samples a single-patch spline: a
/// samples×samples lattice of (s, t) (polycube::cube_face_point order, s fastest), two triangles
/// per lattice cell, and `lines` iso-parameter lines of constant s and of constant t per face,
/// each as 4·(samples−1) segments. Cuboids in order, faces in increasing order within a cuboid.
/// Preconditions (asserted): dimension 3, samples ≥ 2, lines ≥ 2.
GpcBoundaryTessellation tessellate_gpc_boundary(const GpcSpline& spline, int samples, int lines);

}  // namespace volspline::spline
