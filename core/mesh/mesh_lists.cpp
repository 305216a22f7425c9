// SPDX-License-Identifier: MIT
#include "core/mesh/mesh_lists.h"

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

}  // namespace volspline::mesh
