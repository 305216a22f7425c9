// SPDX-License-Identifier: MIT
#include "core/mesh/hex_quality.h"

#include <algorithm>

#include <Eigen/LU>

namespace volspline::mesh {

double scaled_jacobian(const Eigen::Matrix3d& jacobian) {
  const double norms = jacobian.col(0).norm() * jacobian.col(1).norm() * jacobian.col(2).norm();
  return norms > 0.0 ? jacobian.determinant() / norms : -1.0;
}

double hex_min_scaled_jacobian(const std::array<Eigen::Vector3d, 8>& x) {
  double worst = 1.0;
  for (int c = 0; c < 8; ++c) {
    Eigen::Matrix3d edges;
    for (int a = 0; a < 3; ++a) {
      const int other = c ^ (1 << a);
      // Edge vectors point along +axis so that an unfolded hex has det > 0 at every corner.
      edges.col(a) = ((c >> a) & 1) ? Eigen::Vector3d(x[c] - x[other]) : Eigen::Vector3d(x[other] - x[c]);
    }
    worst = std::min(worst, scaled_jacobian(edges));
  }
  return worst;
}

Eigen::Matrix3d hex_principal_axes(const std::array<Eigen::Vector3d, 8>& x) {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Zero();
  for (int c = 0; c < 8; ++c)
    for (int a = 0; a < 3; ++a)
      if (!(c >> a & 1)) axes.col(a) += x[c | (1 << a)] - x[c];
  return axes;
}

double hex_scaled_jacobian(const std::array<Eigen::Vector3d, 8>& x) {
  return std::min(hex_min_scaled_jacobian(x), scaled_jacobian(hex_principal_axes(x)));
}

HexGridQuality hex_grid_quality(const std::array<int, 3>& n, const Positions& xyz) {
  HexGridQuality out;
  for (int k = 0; k + 1 < n[2]; ++k)
    for (int j = 0; j + 1 < n[1]; ++j)
      for (int i = 0; i + 1 < n[0]; ++i) {
        std::array<Eigen::Vector3d, 8> corners;
        for (int c = 0; c < 8; ++c)
          corners[c] = xyz.row((i + (c & 1)) + n[0] * ((j + ((c >> 1) & 1)) + n[1] * (k + ((c >> 2) & 1)))).transpose();
        const double q = hex_scaled_jacobian(corners);
        ++out.num_hexes;
        if (q <= 0.0) ++out.num_inverted;
        out.min_scaled_jacobian = std::min(out.min_scaled_jacobian, q);
      }
  return out;
}

}  // namespace volspline::mesh
