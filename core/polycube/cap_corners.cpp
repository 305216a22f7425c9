// SPDX-License-Identifier: MIT
#include "core/polycube/cap_corners.h"

#include <algorithm>
#include <cmath>

namespace volspline::polycube {

namespace {
// How much longer than its radius a cap's end face may reach (a hemisphere from its equator:
// π/4 of the radius above its middle level, whose radius is 1/√2 of the equator's: 1.11).
constexpr double kCapAspect = 1.5;
}  // namespace

double level_set_length(const mesh::TriangleMesh& m, const std::vector<double>& h, double level) {
  double length = 0.0;
  for (int t = 0; t < m.num_faces(); ++t) {
    std::array<Eigen::RowVector3d, 2> ends;
    int found = 0;
    for (int k = 0; k < 3 && found < 2; ++k) {
      const int a = m.triangles(t, k), b = m.triangles(t, (k + 1) % 3);
      if ((h[a] < level) == (h[b] < level)) continue;
      const double s = (level - h[a]) / (h[b] - h[a]);
      ends[found++] = (1.0 - s) * m.positions.row(a) + s * m.positions.row(b);
    }
    if (found == 2) length += (ends[1] - ends[0]).norm();
  }
  return length;
}

std::array<int, 4> front_corners(const mesh::TriangleMesh& m, const std::vector<double>& h, double level,
                                 const Eigen::Vector3d& pole, const std::array<Eigen::Vector3d, 4>& below) {
  std::vector<char> front(m.num_vertices(), 0);
  for (int t = 0; t < m.num_faces(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = m.triangles(t, k), b = m.triangles(t, (k + 1) % 3);
      if ((h[a] >= level) != (h[b] >= level)) front[h[a] >= level ? a : b] = 1;
    }
  std::vector<int> ids;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int v = 0; v < m.num_vertices(); ++v)
    if (front[v]) {
      ids.push_back(v);
      centre += m.positions.row(v).transpose();
    }
  std::array<int, 4> out = {-1, -1, -1, -1};
  if (ids.size() < 4) return out;
  centre /= static_cast<double>(ids.size());
  const Eigen::Vector3d axis = (pole - centre).normalized();
  const Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  auto angle = [&](const Eigen::Vector3d& x) { return std::atan2((x - centre).dot(e2), (x - centre).dot(e1)); };
  for (int i = 0; i < 4; ++i) {
    const double target = angle(below[i]);
    double best = 10.0;
    for (int v : ids) {
      const double d = std::abs(std::remainder(angle(m.positions.row(v).transpose()) - target, 2.0 * M_PI));
      if (d < best) best = d, out[i] = v;
    }
  }
  return out;
}

double cap_corner_level(const mesh::TriangleMesh& m, const std::vector<double>& height, double pole_height) {
  if (!(pole_height > 0.0)) return 0.5;
  double edges = 0.0;
  for (int t = 0; t < m.num_faces(); ++t)
    for (int k = 0; k < 3; ++k) edges += (m.positions.row(m.triangles(t, k)) - m.positions.row(m.triangles(t, (k + 1) % 3))).norm();
  const double mean_edge = edges / std::max(1, 3 * m.num_faces());
  const double highest = std::clamp(1.0 - 2.0 * mean_edge / pole_height, 0.5, 0.95);
  for (double lambda = 0.5; lambda < highest; lambda += 0.025)
    if ((1.0 - lambda) * pole_height <= kCapAspect * level_set_length(m, height, lambda * pole_height) / (2.0 * M_PI))
      return lambda;
  return highest;
}

}  // namespace volspline::polycube
