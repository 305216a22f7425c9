// SPDX-License-Identifier: MIT
#include "core/spline/jacobian_repair.h"

#include <doctest/doctest.h>

#include "core/spline/bspline_volume.h"
#include "core/spline/tspline_fitting.h"
#include "tests/unit/spline/identity_test_volume.h"

using namespace volspline;

TEST_CASE("the Jacobian repair unfolds an interior fold and keeps the boundary control points") {
  spline::TSpline ts = test::identity_test_volume();
  // Push one interior control point far past its neighbour: the map folds around it.
  Eigen::MatrixXd points = ts.points();
  const int centre = 3 + 7 * (3 + 7 * 3);
  points(centre, 0) += 1.5;  // ∂F/∂u = 1 − 1.5·max|B′_u|·B_v·B_w ≈ 1 − 1.5·2·(2/3)² < 0 right of it
  ts.set_points(points);
  spline::JacobianRepairOptions options;
  options.lattice = 16;
  options.max_iterations = 30;
  const spline::JacobianRepairResult report = spline::repair_jacobian(ts, options);
  CHECK(report.points == 15 * 15 * 15);
  CHECK(report.initial_negative > 0);
  CHECK(report.final_negative == 0);
  CHECK(report.final_min_scaled > 0.0);
  CHECK(report.moved_points > 0);
  const Eigen::Vector3d lo = ts.domain_min(), hi = ts.domain_max();
  for (int i = 0; i < ts.num_functions(); ++i)
    if (spline::touches_exposed_face(ts.knots()[i], lo, hi, polycube::CubeFaceSet::all())) CHECK(ts.points().row(i) == points.row(i));
}

TEST_CASE("the Jacobian repair leaves a valid map alone") {
  spline::TSpline ts = test::identity_test_volume();
  const Eigen::MatrixXd before = ts.points();
  const spline::JacobianRepairResult report = spline::repair_jacobian(ts, {});
  CHECK(report.initial_negative == 0);
  CHECK(report.final_negative == 0);
  CHECK(report.iterations == 0);
  CHECK(report.moved_points == 0);
  CHECK(report.final_min_scaled == doctest::Approx(1.0).epsilon(1e-9));
  CHECK(ts.points() == before);
}
