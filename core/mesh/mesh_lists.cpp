// SPDX-License-Identifier: MIT
#include "core/mesh/mesh_lists.h"

#include <algorithm>

namespace volspline::mesh {

Positions positions_from(const std::vector<Eigen::Vector3d>& points) {
  Positions out(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t v = 0; v < points.size(); ++v) out.row(static_cast<Eigen::Index>(v)) = points[v].transpose();
  return out;
}

Triangles triangles_from(const std::vector<std::array<int, 3>>& tris) {
  Triangles out(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) out(static_cast<Eigen::Index>(t), k) = tris[t][k];
  return out;
}

std::vector<std::array<int, 3>> split_at_midpoints(const std::array<int, 3>& tri, const EdgeMidpoints& midpoint,
                                                   int first_midpoint) {
  auto mid = [&](int a, int b) {
    const auto it = midpoint.find({std::min(a, b), std::max(a, b)});
    return it == midpoint.end() ? -1 : it->second;
  };
  // The corners and midpoints in order, from the corner opposite the last split edge.
  int first = 0;
  for (int k = 0; k < 3; ++k)
    if (mid(tri[k], tri[(k + 1) % 3]) >= 0) first = (k + 2) % 3;
  std::vector<int> ring;
  for (int j = 0; j < 3; ++j) {
    const int a = tri[(first + j) % 3], b = tri[(first + j + 1) % 3];
    ring.push_back(a);
    if (mid(a, b) >= 0) ring.push_back(mid(a, b));
  }
  if (ring.size() == 3) return {tri};
  std::vector<std::array<int, 3>> parts;
  std::vector<int> rest;
  const int r = static_cast<int>(ring.size());
  for (int i = 0; i < r; ++i) {
    const int prev = ring[(i + r - 1) % r], cur = ring[i], next = ring[(i + 1) % r];
    if (cur < first_midpoint && prev >= first_midpoint && next >= first_midpoint) parts.push_back({prev, cur, next});
    else rest.push_back(cur);
  }
  for (std::size_t i = 1; i + 1 < rest.size(); ++i) parts.push_back({rest[0], rest[i], rest[i + 1]});
  return parts;
}

}  // namespace volspline::mesh
