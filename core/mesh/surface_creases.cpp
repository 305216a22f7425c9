// SPDX-License-Identifier: MIT
#include "core/mesh/surface_creases.h"

#include <cassert>
#include <cmath>

#include <Eigen/Eigenvalues>

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

SurfaceCreases::SurfaceCreases(const TriangleMesh& surface, double angle_rad, double scale)
    : surface_(surface), cos_crease_(std::cos(angle_rad)) {
  assert(angle_rad >= 0.0 && angle_rad <= 3.15 && scale >= 0.0);
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
  if (scale > 0.0 && nt > 0) {
    double length = 0.0;
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k)
        length += (surface.positions.row(surface.triangles(t, k)) - surface.positions.row(surface.triangles(t, (k + 1) % 3))).norm();
    radius_ = scale * length / (3.0 * nt);
    vertex_seen_.assign(nv, 0);
    triangle_seen_.assign(nt, 0);
  }
}

bool SurfaceCreases::holds_at_scale(int v) const {
  // The triangles reached from v's star through vertices within radius_ of v, in visit order
  // (marked with this visit's stamp: a dense region's disc may hold thousands of them).
  const Eigen::Vector3d centre = surface_.positions.row(v).transpose();
  ++stamp_;
  std::vector<int> vertices{v}, triangles;
  vertex_seen_[v] = stamp_;
  for (std::size_t next = 0; next < vertices.size(); ++next) {
    const int u = vertices[next];
    for (int i = star_begin_[u]; i < star_begin_[u + 1]; ++i) {
      const int t = star_[i];
      if (triangle_seen_[t] == stamp_) continue;
      triangle_seen_[t] = stamp_;
      triangles.push_back(t);
      for (int k = 0; k < 3; ++k) {
        const int w = surface_.triangles(t, k);
        if (vertex_seen_[w] != stamp_ && (surface_.positions.row(w).transpose() - centre).norm() <= radius_) {
          vertex_seen_[w] = stamp_;
          vertices.push_back(w);
        }
      }
    }
  }
  Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
  for (const int t : triangles) {
    const Eigen::Vector3d a = surface_.positions.row(surface_.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = surface_.positions.row(surface_.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = surface_.positions.row(surface_.triangles(t, 2)).transpose();
    const Eigen::Vector3d n = (b - a).cross(c - a);  // |n| = 2·area: Σ A nnᵀ up to a factor 2
    const double norm = n.norm();
    if (norm > 0.0) tensor += n * n.transpose() / norm;
  }
  const Eigen::Vector3d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(tensor, Eigen::EigenvaluesOnly).eigenvalues();
  return lambda(2) > 0.0 && lambda(1) >= kSecondNormal * lambda(2);
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
  if (crease && radius_ > 0.0) crease = holds_at_scale(v);
  state_[v] = crease ? 1 : 0;
  return crease;
}

bool SurfaceCreases::triangle_near_crease(int t) const {
  return vertex_on_crease(surface_.triangles(t, 0)) || vertex_on_crease(surface_.triangles(t, 1)) ||
         vertex_on_crease(surface_.triangles(t, 2));
}

std::vector<char> crease_triangles(const TriangleMesh& surface, double angle_rad, double scale) {
  const SurfaceCreases creases(surface, angle_rad, scale);
  std::vector<char> out(surface.num_faces());
  for (int t = 0; t < surface.num_faces(); ++t) out[t] = creases.triangle_near_crease(t);
  return out;
}

}  // namespace volspline::mesh
