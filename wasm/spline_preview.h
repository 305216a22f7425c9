// SPDX-License-Identifier: MIT
#pragma once
// View data of a geometric T-spline for the browser's WebGL view: flat float arrays, nothing
// the page has to interpret beyond "3 floats per point".
#include <cstdint>
#include <vector>

#include "core/spline/tspline.h"

namespace volspline::wasm {

/// Boundary surface, iso-parameter lines and control points of a spline of dimension 3.
struct SplinePreview {
  std::vector<float> surface_xyz;                ///< 6·samples² points, 3 floats each
  std::vector<float> surface_uvw;                ///< their parameters as fractions of the domain box, [0, 1]³
  std::vector<std::uint32_t> surface_triangles;  ///< 3 ids per triangle, outward on every face
  std::vector<float> line_xyz;                   ///< line segments, 2 points (6 floats) each
  std::vector<float> line_uvw;                   ///< their parameters as fractions of the domain box
  std::vector<float> control_xyz;                ///< the control points p_i, 3 floats each
};

/// Samples the 6 domain faces on a samples×samples lattice and `lines` iso-parameter lines per
/// direction per face (each line as 4·(samples−1) segments). Preconditions: dimension 3,
/// samples ≥ 2, lines ≥ 2.
SplinePreview spline_preview(const spline::TSpline& spline, int samples, int lines);

/// A cut through the spline volume at a constant parameter, coloured by scaled Jacobian.
struct SplineCut {
  std::vector<float> xyz;                  ///< samples² points F(uvw) with uvw[axis] fixed
  std::vector<std::uint32_t> triangles;    ///< 3 ids per triangle
  std::vector<float> scaled_jacobian;      ///< per point det J / (|J_u| |J_v| |J_w|), in [−1, 1]
  std::vector<float> uvw;                  ///< per point its parameters in the spline's domain, 3 floats
  float min_scaled_jacobian = 1;           ///< smallest of scaled_jacobian
};

/// The iso-parameter surface uvw[axis] = lo + t·(hi − lo) of the domain, sampled on a
/// samples×samples lattice. Preconditions: dimension 3, axis in 0..2, t in [0, 1], samples ≥ 2.
SplineCut spline_cut(const spline::TSpline& spline, int axis, double t, int samples);

}  // namespace volspline::wasm
