// SPDX-License-Identifier: MIT
#include "core/mesh/surface_creases.h"

#include <cassert>
#include <cmath>

namespace volspline::mesh {

namespace {

Eigen::Vector3d unit_normal(const TriangleMesh& surface, int t) {
  const Eigen::Vector3d a = surface.positions.row(surface.triangles(t, 0)).transpose();
  const Eigen::Vector3d b = surface.positions.row(surface.triangles(t, 1)).transpose();
  const Eigen::Vector3d c = surface.positions.row(surface.triangles(t, 2)).transpose();
  return (b - a).cross(c - a).normalized();
}

bool has_vertex(const TriangleMesh& surface, int t, int v) {
  return surface.triangles(t, 0) == v || surface.triangles(t, 1) == v || surface.triangles(t, 2) == v;
}

}  // namespace

SurfaceCreases::SurfaceCreases(const TriangleMesh& surface, double angle_rad)
    : surface_(surface), cos_crease_(std::cos(angle_rad)) {
  assert(angle_rad >= 0.0 && angle_rad <= 3.15);
  const int nv = surface.num_vertices(), nt = surface.num_faces();
  star_begin_.assign(nv + 1, 0);
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) ++star_begin_[surface.triangles(t, k) + 1];
  for (int v = 0; v < nv; ++v) star_begin_[v + 1] += star_begin_[v];
  star_.resize(star_begin_[nv]);
  std::vector<int> fill(star_begin_.begin(), star_begin_.end() - 1);
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) star_[fill[surface.triangles(t, k)]++] = t;
  state_.assign(nv, -1);
}

bool SurfaceCreases::vertex_on_crease(int v) const {
  if (state_[v] >= 0) return state_[v] == 1;
  bool crease = false;
  // Each edge (v, w): the triangles of v's star that hold w.
  for (int i = star_begin_[v]; i < star_begin_[v + 1] && !crease; ++i)
    for (int k = 0; k < 3 && !crease; ++k) {
      const int w = surface_.triangles(star_[i], k);
      if (w == v) continue;
      int first = -1, second = -1, count = 0;
      for (int j = star_begin_[v]; j < star_begin_[v + 1]; ++j)
        if (has_vertex(surface_, star_[j], w)) {
          ++count;
          (first < 0 ? first : second) = star_[j];
        }
      // NaN normals (zero area) compare false, so they count as a crease.
      if (count == 2 && !(unit_normal(surface_, first).dot(unit_normal(surface_, second)) >= cos_crease_)) crease = true;
    }
  state_[v] = crease ? 1 : 0;
  return crease;
}

bool SurfaceCreases::triangle_near_crease(int t) const {
  return vertex_on_crease(surface_.triangles(t, 0)) || vertex_on_crease(surface_.triangles(t, 1)) ||
         vertex_on_crease(surface_.triangles(t, 2));
}

std::vector<char> crease_triangles(const TriangleMesh& surface, double angle_rad) {
  const SurfaceCreases creases(surface, angle_rad);
  std::vector<char> out(surface.num_faces());
  for (int t = 0; t < surface.num_faces(); ++t) out[t] = creases.triangle_near_crease(t);
  return out;
}

}  // namespace volspline::mesh
