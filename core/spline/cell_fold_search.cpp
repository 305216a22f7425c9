// SPDX-License-Identifier: MIT
#include "core/spline/cell_fold_search.h"

#include <algorithm>
#include <cassert>

#include <Eigen/LU>

namespace volspline::spline {

namespace {

double det_at(const BezierCell& cell, const Eigen::Vector3d& s) {
  double value[3];
  Eigen::Matrix3d jacobian;
  evaluate_bezier_cell(cell, s, value, jacobian.data());
  return jacobian.determinant();
}

}  // namespace

CellJacobianPoint lowest_jacobian_point(const BezierCell& cell, const Eigen::Vector3d& start) {
  assert(cell.dimension == 3);
  CellJacobianPoint best{start, det_at(cell, start)};
  for (int k = 0; k <= 4; ++k)
    for (int j = 0; j <= 4; ++j)
      for (int i = 0; i <= 4; ++i) {
        const Eigen::Vector3d s(0.25 * i, 0.25 * j, 0.25 * k);
        const double det = det_at(cell, s);
        if (det < best.det_j) best = {s, det};
      }
  for (double h = 0.125; h >= 1.0 / 1024.0;) {
    CellJacobianPoint next = best;
    for (int n = 0; n < 27; ++n) {
      if (n == 13) continue;
      const Eigen::Vector3d step(n % 3 - 1, n / 3 % 3 - 1, n / 9 - 1);
      const Eigen::Vector3d s = (best.s + h * step).cwiseMax(0.0).cwiseMin(1.0);
      const double det = det_at(cell, s);
      if (det < next.det_j) next = {s, det};
    }
    if (next.det_j < best.det_j) best = next;
    else h *= 0.5;
  }
  return best;
}

}  // namespace volspline::spline
