// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/polycube/cube_faces.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// The boundary surface of a geometric spline (dimension 3) and iso-parameter lines on it, as
/// flat float arrays (viewers and glTF read them as they are).
struct BoundaryTessellation {
  std::vector<float> surface_xyz;                ///< samples² points per face, 3 floats each, model units
  std::vector<float> surface_uvw;                ///< their parameters as fractions of the domain box, [0, 1]³
  std::vector<std::uint32_t> surface_triangles;  ///< 3 point ids per triangle, outward on every face
  std::vector<float> line_xyz;                   ///< line segments, 2 points (6 floats) each
  std::vector<float> line_uvw;                   ///< their parameters as fractions of the domain box
};

/// Samples each face f in `faces` of the domain box (polycube::cube_face_point order) on a
/// samples×samples lattice of (s, t), two triangles per lattice cell, and `lines` iso-parameter
/// lines of constant s and of constant t per face, each as 4·(samples−1) segments. Faces come in
/// increasing order, each face's points row by row (s fastest). Preconditions (asserted):
/// dimension 3, samples ≥ 2, lines ≥ 2.
BoundaryTessellation tessellate_boundary(const TSpline& spline, int samples, int lines,
                                         polycube::CubeFaceSet faces = polycube::CubeFaceSet::all());

/// Appends one face (polycube::cube_face_point numbering) of the unit box to `out` as
/// tessellate_boundary samples it: points, triangles (ids continue after out's points), lines.
/// evaluate maps a point of the unit box to model units. Preconditions: samples ≥ 2, lines ≥ 2.
void append_face_tessellation(int face, int samples, int lines,
                              const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& evaluate,
                              BoundaryTessellation& out);
/// Appends two triangles per cell of an m×m lattice of points base + i + m·j, counter-clockwise
/// in (i, j); `flip` reverses them.
void append_lattice_triangles(std::vector<std::uint32_t>& out, std::uint32_t base, int m, bool flip);

}  // namespace volspline::spline
