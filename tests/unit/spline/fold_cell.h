// SPDX-License-Identifier: MIT
// A Bézier cell with a known det J for the certificate and fold search tests.
#pragma once

#include "core/spline/bezier_extraction.h"

namespace volspline::spline::test {

// The unit cell of F(s) = (s0, s1, g(s)) with ∂g/∂s2 = (s0 − a)² + (s1 − b)² + (s2 − c)² − r2,
// i.e. g = ((s0 − a)² + (s1 − b)² − r2)·s2 + (s2 − c)³/3 (tricubic): det J = ∂g/∂s2, lowest
// (−r2) at exactly (a, b, c); for r2 > 0 negative only in the ball of radius √r2 around it, for
// r2 < 0 no fold (det J ≥ −r2 > 0).
inline BezierCell fold_cell(double a, double b, double c, double r2) {
  double power[64 * 3] = {};
  auto at = [&](int eu, int ev, int ew, int d) -> double& { return power[((4 * eu + ev) * 4 + ew) * 3 + d]; };
  at(1, 0, 0, 0) = 1.0;
  at(0, 1, 0, 1) = 1.0;
  // ((s0 − a)² + (s1 − b)² − r²)·s2
  at(2, 0, 1, 2) += 1.0;
  at(1, 0, 1, 2) += -2.0 * a;
  at(0, 2, 1, 2) += 1.0;
  at(0, 1, 1, 2) += -2.0 * b;
  at(0, 0, 1, 2) += a * a + b * b - r2;
  // (s2 − c)³/3 = s2³/3 − c·s2² + c²·s2 − c³/3
  at(0, 0, 3, 2) += 1.0 / 3.0;
  at(0, 0, 2, 2) += -c;
  at(0, 0, 1, 2) += c * c;
  at(0, 0, 0, 2) += -c * c * c / 3.0;
  BezierCell cell;
  cell.dimension = 3;
  cell.uvw_min = Eigen::Vector3d::Zero();
  cell.uvw_max = Eigen::Vector3d::Ones();
  power_to_bernstein(power, 3, cell.points.data());
  cell.weights.fill(1.0);
  return cell;
}

}  // namespace volspline::spline::test
