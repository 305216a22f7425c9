// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <vector>

#include "core/spline/gpc_spline.h"

namespace volspline::spline {

/// A cut through every cuboid of a geometric GPC spline at a constant local parameter, with the
/// scaled Jacobian of F at each point (the browser's cut view).
struct GpcSplineCut {
  std::vector<float> xyz;                ///< samples² points F(uvw) per cuboid, 3 floats each, model units
  std::vector<std::uint32_t> cuboid;     ///< the cuboid of each point
  std::vector<float> uvw;                ///< per point its local coordinates in that cuboid, 3 floats
  std::vector<std::uint32_t> triangles;  ///< 3 point ids per triangle
  std::vector<float> scaled_jacobian;    ///< per point, mesh::scaled_jacobian of F's Jacobian, in [−1, 1]
  float min_scaled_jacobian = 1;         ///< smallest of scaled_jacobian (1 if there are none)
};

/// In every cuboid c, the plane uvw[axis] = t·size[axis] of its local coordinates, sampled on a
/// samples×samples lattice of the other two axes (polycube::cube_face_point order of face
/// 2·axis, s fastest), two triangles per lattice cell. Cuboids in order. The axes of two cuboids
/// need not match in model space, so the pieces meet only where the transition maps keep the axis.
/// Preconditions (asserted): dimension 3, axis in 0..2, t in [0, 1], samples ≥ 2.
GpcSplineCut gpc_spline_cut(const GpcSpline& spline, int axis, double t, int samples);

}  // namespace volspline::spline
