// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>

#include "core/spline/bezier_extraction.h"
#include "core/spline/cell_fold_search.h"
#include "fold_cell.h"

using volspline::spline::BezierCell;
using volspline::spline::CellJacobianPoint;
using volspline::spline::lowest_jacobian_point;
using volspline::spline::test::fold_cell;

TEST_CASE("lowest_jacobian_point finds a fold inside the cell, between the grid points") {
  // A fold of radius 0.05 centred off the 5³ grid and off the certificate's box corners.
  const BezierCell cell = fold_cell(0.31, 0.68, 0.93, 0.0025);
  const CellJacobianPoint p = lowest_jacobian_point(cell, Eigen::Vector3d::Zero());
  CHECK(std::abs(p.s(0) - 0.31) < 2e-3);
  CHECK(std::abs(p.s(1) - 0.68) < 2e-3);
  CHECK(std::abs(p.s(2) - 0.93) < 2e-3);
  // det J there is −0.0025 up to the search's resolution (quadratic in the distance).
  CHECK(p.det_j == doctest::Approx(-0.0025).epsilon(0.01));
  // The extraction reproduces the map: det J at the centre is exactly −0.0025 (to rounding).
  double value[3];
  Eigen::Matrix3d jacobian;
  volspline::spline::evaluate_bezier_cell(cell, Eigen::Vector3d(0.31, 0.68, 0.93), value, jacobian.data());
  CHECK(jacobian.determinant() == doctest::Approx(-0.0025).epsilon(1e-12));
}

TEST_CASE("lowest_jacobian_point on a cell without fold stays at its lowest point, det J > 0") {
  // No fold: det J ≥ 0.04 with its minimum at (0.5, 0.5, 1) clamped onto the face.
  BezierCell cell = fold_cell(0.5, 0.5, 1.2, 0.0);
  const CellJacobianPoint p = lowest_jacobian_point(cell, Eigen::Vector3d(0.5, 0.5, 0.5));
  CHECK(std::abs(p.s(0) - 0.5) < 1e-9);
  CHECK(std::abs(p.s(1) - 0.5) < 1e-9);
  CHECK(p.s(2) == 1.0);
  CHECK(p.det_j == doctest::Approx(0.04).epsilon(1e-9));
}
