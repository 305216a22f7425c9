// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::mesh {

/// Creases of a triangle soup or mesh, found where they are asked for: an edge (two triangles
/// sharing the same two vertex ids, and no third) is a crease if their unit normals make an
/// angle above angle_rad (or either normal is undefined: a zero-area triangle); a vertex is on a
/// crease if one of its edges is. Edges with one triangle or more than two are not creases.
/// With scale > 0 a crease must also hold at that scale: the triangles within scale times the
/// mean edge length of the vertex (through shared vertices) must show two normal directions,
/// the second eigenvalue of their area-weighted normal tensor Σ A nnᵀ at least kSecondNormal of
/// the first. A real crease (a cube's edge, a claw's ridge) passes; a ripple or a sliver's
/// stray normal in a noisy triangulation (a scan, marching cubes) does not.
/// Building costs one pass over the triangles; each vertex is examined once, when first asked.
/// The surface must outlive this object. angle_rad in [0, π], scale ≥ 0.
class SurfaceCreases {
 public:
  /// λ₂/λ₁ of the normal tensor at or above which a crease holds at the scale: two planes of
  /// equal area meeting at θ give tan²(θ/2), 0.25 at 53°.
  static constexpr double kSecondNormal = 0.25;
  SurfaceCreases(const TriangleMesh& surface, double angle_rad, double scale = 0.0);
  /// True if vertex v lies on a crease. v in [0, num_vertices).
  bool vertex_on_crease(int v) const;
  /// True if one of triangle t's vertices lies on a crease. t in [0, num_faces).
  bool triangle_near_crease(int t) const;

 private:
  const TriangleMesh& surface_;
  double cos_crease_;
  double radius_ = 0.0;  // scale times the mean edge length (0: no scale test)
  bool holds_at_scale(int v) const;
  std::vector<int> star_begin_;     // per vertex, its range of star_ (num_vertices + 1)
  std::vector<int> star_;           // triangles around each vertex, ascending ids
  mutable std::vector<signed char> state_;  // per vertex: −1 not examined yet, 0 no crease, 1 crease
  mutable int stamp_ = 0;  // holds_at_scale's visit count: marks below equal to it are this visit's
  mutable std::vector<int> vertex_seen_, triangle_seen_;
};

/// Per triangle, SurfaceCreases::triangle_near_crease for all of them.
std::vector<char> crease_triangles(const TriangleMesh& surface, double angle_rad, double scale = 0.0);

}  // namespace volspline::mesh
