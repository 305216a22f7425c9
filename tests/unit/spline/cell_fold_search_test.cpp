// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>

#include "core/spline/bezier_extraction.h"
#include "core/spline/cell_fold_search.h"
#include "core/spline/jacobian_certificate.h"

using volspline::spline::BezierCell;
using volspline::spline::CellJacobianPoint;
using volspline::spline::lowest_jacobian_point;
using volspline::spline::power_to_bernstein;

namespace {

// The unit cell of F(s) = (s0, s1, g(s)) with ∂g/∂s2 = (s0 − a)² + (s1 − b)² + (s2 − c)² − r²,
// i.e. g = ((s0 − a)² + (s1 − b)² − r²)·s2 + (s2 − c)³/3 (tricubic): det J = ∂g/∂s2, lowest
// (−r²) at exactly (a, b, c), and negative only in the ball of radius r around it.
BezierCell fold_cell(double a, double b, double c, double r) {
  double power[64 * 3] = {};
  auto at = [&](int eu, int ev, int ew, int d) -> double& { return power[((4 * eu + ev) * 4 + ew) * 3 + d]; };
  at(1, 0, 0, 0) = 1.0;
  at(0, 1, 0, 1) = 1.0;
  // ((s0 − a)² + (s1 − b)² − r²)·s2
  at(2, 0, 1, 2) += 1.0;
  at(1, 0, 1, 2) += -2.0 * a;
  at(0, 2, 1, 2) += 1.0;
  at(0, 1, 1, 2) += -2.0 * b;
  at(0, 0, 1, 2) += a * a + b * b - r * r;
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

}  // namespace

TEST_CASE("lowest_jacobian_point finds a fold inside the cell, between the grid points") {
  // A fold of radius 0.05 centred off the 5³ grid and off the certificate's box corners.
  const BezierCell cell = fold_cell(0.31, 0.68, 0.93, 0.05);
  const CellJacobianPoint p = lowest_jacobian_point(cell, Eigen::Vector3d::Zero());
  CHECK(std::abs(p.s(0) - 0.31) < 2e-3);
  CHECK(std::abs(p.s(1) - 0.68) < 2e-3);
  CHECK(std::abs(p.s(2) - 0.93) < 2e-3);
  // det J there is −r² up to the search's resolution (quadratic in the distance).
  CHECK(p.det_j == doctest::Approx(-0.0025).epsilon(0.01));
  // The extraction reproduces the map: det J at the centre is exactly −r² (to rounding).
  double value[3];
  Eigen::Matrix3d jacobian;
  volspline::spline::evaluate_bezier_cell(cell, Eigen::Vector3d(0.31, 0.68, 0.93), value, jacobian.data());
  CHECK(jacobian.determinant() == doctest::Approx(-0.0025).epsilon(1e-12));
}

TEST_CASE("lowest_jacobian_point on a cell without fold stays at its lowest point, det J > 0") {
  // r² < 0 is no fold: det J ≥ 0.01 with its minimum at (0.5, 0.5, 1) clamped onto the face.
  BezierCell cell = fold_cell(0.5, 0.5, 1.2, 0.0);
  const CellJacobianPoint p = lowest_jacobian_point(cell, Eigen::Vector3d(0.5, 0.5, 0.5));
  CHECK(std::abs(p.s(0) - 0.5) < 1e-9);
  CHECK(std::abs(p.s(1) - 0.5) < 1e-9);
  CHECK(p.s(2) == 1.0);
  CHECK(p.det_j == doctest::Approx(0.04).epsilon(1e-9));
}
