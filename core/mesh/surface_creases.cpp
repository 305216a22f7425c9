// SPDX-License-Identifier: MIT
#include "core/mesh/surface_creases.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace volspline::mesh {

std::vector<char> crease_triangles(const TriangleMesh& surface, double angle_rad) {
  assert(angle_rad >= 0.0 && angle_rad <= 3.15);
  const int nt = surface.num_faces();
  std::vector<Eigen::Vector3d> normal(nt);
  for (int t = 0; t < nt; ++t) {
    const Eigen::Vector3d a = surface.positions.row(surface.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = surface.positions.row(surface.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = surface.positions.row(surface.triangles(t, 2)).transpose();
    normal[t] = (b - a).cross(c - a).normalized();
  }
  std::vector<std::array<int, 3>> edges;  // (low vertex, high vertex, triangle), sorted
  edges.reserve(3 * static_cast<std::size_t>(nt));
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = surface.triangles(t, k), w = surface.triangles(t, (k + 1) % 3);
      edges.push_back({std::min(u, w), std::max(u, w), t});
    }
  std::sort(edges.begin(), edges.end());
  std::vector<char> crease_vertex(surface.num_vertices(), 0);
  const double cos_crease = std::cos(angle_rad);
  for (std::size_t e = 0; e < edges.size();) {
    std::size_t end = e + 1;
    while (end < edges.size() && edges[end][0] == edges[e][0] && edges[end][1] == edges[e][1]) ++end;
    // NaN normals (zero area) compare false, so they count as a crease.
    if (end == e + 2 && !(normal[edges[e][2]].dot(normal[edges[e + 1][2]]) >= cos_crease))
      crease_vertex[edges[e][0]] = crease_vertex[edges[e][1]] = 1;
    e = end;
  }
  std::vector<char> crease(nt, 0);
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) crease[t] = crease[t] || crease_vertex[surface.triangles(t, k)];
  return crease;
}

}  // namespace volspline::mesh
