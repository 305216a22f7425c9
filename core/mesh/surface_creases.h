// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::mesh {

/// Creases of a triangle soup or mesh, found where they are asked for: an edge (two triangles
/// sharing the same two vertex ids, and no third) is a crease if their unit normals make an
/// angle above angle_rad (or either normal is undefined: a zero-area triangle); a vertex is on a
/// crease if one of its edges is. Edges with one triangle or more than two are not creases.
/// Building costs one pass over the triangles; each vertex is examined once, when first asked.
/// The surface must outlive this object. angle_rad in [0, π].
class SurfaceCreases {
 public:
  SurfaceCreases(const TriangleMesh& surface, double angle_rad);
  /// True if vertex v lies on a crease. v in [0, num_vertices).
  bool vertex_on_crease(int v) const;
  /// True if one of triangle t's vertices lies on a crease. t in [0, num_faces).
  bool triangle_near_crease(int t) const;

 private:
  const TriangleMesh& surface_;
  double cos_crease_;
  std::vector<int> star_begin_;     // per vertex, its range of star_ (num_vertices + 1)
  std::vector<int> star_;           // triangles around each vertex, ascending ids
  mutable std::vector<signed char> state_;  // per vertex: −1 not examined yet, 0 no crease, 1 crease
};

/// Per triangle, SurfaceCreases::triangle_near_crease for all of them.
std::vector<char> crease_triangles(const TriangleMesh& surface, double angle_rad);

}  // namespace volspline::mesh
