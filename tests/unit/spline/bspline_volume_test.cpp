// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/spline/bspline_volume.h"

using volspline::Error;
using volspline::spline::boundary_restricted_knots;
using volspline::spline::BsplineVolume;

namespace {

// Trilinear map with all 8 tensor terms; cubic B-splines reproduce it exactly from control
// points placed at the Greville abscissae (linear precision per axis, tensor product).
Eigen::Vector3d trilinear(const Eigen::Vector3d& p) {
  const double u = p[0], v = p[1], w = p[2];
  return {1.0 + 2.0 * u - 0.5 * v + 0.25 * w + 0.3 * u * v,
          -0.7 + 0.1 * u + 1.5 * v + 0.2 * u * w - 0.4 * u * v * w,
          0.5 - 0.3 * u + 0.2 * v + 1.1 * w + 0.6 * v * w};
}

Eigen::Matrix3d trilinear_jacobian(const Eigen::Vector3d& p) {
  const double u = p[0], v = p[1], w = p[2];
  Eigen::Matrix3d j;
  j << 2.0 + 0.3 * v, -0.5 + 0.3 * u, 0.25,
       0.1 + 0.2 * w - 0.4 * v * w, 1.5 - 0.4 * u * w, 0.2 * u - 0.4 * u * v,
       -0.3, 0.2 + 0.6 * w, 1.1 + 0.6 * v;
  return j;
}

std::array<std::vector<double>, 3> test_knots() {
  return {boundary_restricted_knots({0.0, 0.3, 0.35, 1.0}),
          boundary_restricted_knots({-1.0, 0.0, 2.0}),
          std::vector<double>{0, 0, 0, 0, 0.5, 0.5, 0.7, 1, 1, 1, 1}};
}

BsplineVolume greville_volume() {
  const auto knots = test_knots();
  const int n[3] = {int(knots[0].size()) - 4, int(knots[1].size()) - 4, int(knots[2].size()) - 4};
  Eigen::MatrixXd points(n[0] * n[1] * n[2], 3);
  // Build with dummy points first to use greville_abscissa and control_index.
  BsplineVolume probe(knots, Eigen::MatrixXd::Zero(points.rows(), 3));
  for (int i2 = 0; i2 < n[2]; ++i2)
    for (int i1 = 0; i1 < n[1]; ++i1)
      for (int i0 = 0; i0 < n[0]; ++i0) {
        const Eigen::Vector3d g(probe.greville_abscissa(0, i0), probe.greville_abscissa(1, i1),
                                probe.greville_abscissa(2, i2));
        points.row(probe.control_index(i0, i1, i2)) = trilinear(g).transpose();
      }
  return BsplineVolume(knots, points);
}

std::vector<Eigen::Vector3d> random_parameters(const BsplineVolume& volume, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector3d lo = volume.domain_min(), hi = volume.domain_max();
  std::vector<Eigen::Vector3d> out;
  // The 8 corners first: the closed upper domain end must evaluate correctly.
  for (int c = 0; c < 8; ++c) {
    out.emplace_back(c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]);
  }
  while (int(out.size()) < count) {
    out.emplace_back(lo[0] + (hi[0] - lo[0]) * unit(rng), lo[1] + (hi[1] - lo[1]) * unit(rng),
                     lo[2] + (hi[2] - lo[2]) * unit(rng));
  }
  return out;
}

}  // namespace

TEST_CASE("boundary restricted knots replicate the ends 3 times") {
  CHECK(boundary_restricted_knots({0, 1, 2}) == std::vector<double>{0, 0, 0, 0, 1, 2, 2, 2, 2});
  CHECK_THROWS_WITH_AS(boundary_restricted_knots({0}), "boundary knots: need at least 2 grid coordinates", Error);
  CHECK_THROWS_WITH_AS(boundary_restricted_knots({0, 1, 1}),
                       "boundary knots: grid coordinate 2 is not larger than the one before", Error);
  CHECK_THROWS_WITH_AS(boundary_restricted_knots({0, std::numeric_limits<double>::quiet_NaN()}),
                       "boundary knots: grid coordinate 1 is not finite", Error);
}

TEST_CASE("B-spline volume reproduces a trilinear map and its Jacobian exactly") {
  const BsplineVolume volume = greville_volume();
  CHECK(volume.dimension() == 3);
  CHECK(volume.num_control(0) == 6);
  CHECK(volume.num_control(2) == 7);
  for (const Eigen::Vector3d& p : random_parameters(volume, 500, 1)) {
    CAPTURE(p.transpose());
    // Exact identity up to rounding of O(1) values: 1e-12.
    CHECK((volume.evaluate(p) - trilinear(p)).norm() < 1e-12);
    CHECK((volume.jacobian(p) - trilinear_jacobian(p)).norm() < 1e-12);
    CHECK(volume.derivative(p, {0, 0, 0}).isApprox(volume.evaluate(p), 1e-14));
    // Trilinear: no second derivative along one axis.
    CHECK(volume.derivative(p, {2, 0, 0}).norm() < 1e-10);
  }
}

TEST_CASE("B-spline volume derivatives match finite differences") {
  const auto knots = test_knots();
  const int rows = (int(knots[0].size()) - 4) * (int(knots[1].size()) - 4) * (int(knots[2].size()) - 4);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd points(rows, 2);
  for (int i = 0; i < rows; ++i) points.row(i) << normal(rng), normal(rng);
  const BsplineVolume volume(knots, points);
  const double h = 1e-6;
  for (const Eigen::Vector3d& p : random_parameters(volume, 200, 2)) {
    if ((p - volume.domain_min()).minCoeff() < 2 * h || (volume.domain_max() - p).minCoeff() < 2 * h) continue;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[a] = h;
      std::array<int, 3> first = {0, 0, 0}, second = {0, 0, 0};
      first[a] = 1;
      second[a] = 2;
      // Central differences, O(h²) truncation; a stencil across a C1 knot still gives O(h) on the
      // second derivative, so compare second derivatives with the first-derivative difference.
      const Eigen::VectorXd fd = (volume.evaluate(p + e) - volume.evaluate(p - e)) / (2 * h);
      const Eigen::VectorXd d1 = volume.derivative(p, first);
      CHECK((fd - d1).norm() <= 1e-6 * std::max(1.0, d1.norm()));
      CHECK((volume.jacobian(p).col(a) - d1).norm() < 1e-12);
      const Eigen::VectorXd fd2 = (volume.derivative(p + e, first) - volume.derivative(p - e, first)) / (2 * h);
      const Eigen::VectorXd d2 = volume.derivative(p, second);
      if (std::abs(p[2] - 0.5) > 2 * h) CHECK((fd2 - d2).norm() <= 1e-5 * std::max(1.0, d2.norm()));
    }
  }
}

TEST_CASE("span lookup by binary search") {
  const BsplineVolume volume = greville_volume();
  // Axis 0 knots: 0 0 0 0 0.3 0.35 1 1 1 1 (6 functions, spans 3..5).
  CHECK(volume.find_span(0, 0.0) == 3);
  CHECK(volume.find_span(0, 0.29) == 3);
  CHECK(volume.find_span(0, 0.3) == 4);
  CHECK(volume.find_span(0, 0.5) == 5);
  CHECK(volume.find_span(0, 1.0) == 5);
  // Axis 2 knots: 0 0 0 0 0.5 0.5 0.7 1 1 1 1, the double knot has an empty span.
  CHECK(volume.find_span(2, 0.5) == 5);
  CHECK(volume.find_span(2, 0.49) == 3);
  CHECK(volume.find_span(2, 1.0) == 6);
}

TEST_CASE("batch evaluation equals single evaluation") {
  const BsplineVolume volume = greville_volume();
  const auto params = random_parameters(volume, 50, 3);
  Eigen::MatrixX3d uvw(params.size(), 3);
  for (size_t i = 0; i < params.size(); ++i) uvw.row(i) = params[i].transpose();
  const Eigen::MatrixXd out = volume.evaluate_batch(uvw);
  for (size_t i = 0; i < params.size(); ++i) CHECK(out.row(i).transpose() == volume.evaluate(params[i]));
  uvw(7, 1) = 5.0;
  CHECK_THROWS_WITH_AS(volume.evaluate_batch(uvw),
                       "row 7: B-spline volume: parameter v = 5.000000 is outside the domain [-1.000000, 2.000000]",
                       Error);
}

TEST_CASE("B-spline volume rejects broken input with a message") {
  auto knots = test_knots();
  const Eigen::MatrixXd points = Eigen::MatrixXd::Zero(6 * 5 * 7, 3);
  auto broken = knots;
  broken[1] = {0, 0, 0, 0, 1, 1, 1};
  CHECK_THROWS_WITH_AS(BsplineVolume(broken, points),
                       "B-spline volume: knot vector v has 7 knots, need at least 8 (4 basis functions)", Error);
  broken = knots;
  broken[0][5] = 0.1;
  CHECK_THROWS_WITH_AS(BsplineVolume(broken, points),
                       "B-spline volume: knot vector u: knot 5 is smaller than the knot before it", Error);
  broken = knots;
  broken[2][2] = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH_AS(BsplineVolume(broken, points), "B-spline volume: knot vector w: knot 2 is not finite", Error);
  broken = knots;
  broken[0][0] = -1.0;
  CHECK_THROWS_WITH_AS(BsplineVolume(broken, points),
                       "B-spline volume: knot vector u is not clamped (first 4 and last 4 knots must be equal)", Error);
  broken = knots;
  broken[2] = {0, 0, 0, 0, 0.5, 0.5, 0.5, 0.5, 1, 1, 1, 1};
  CHECK_THROWS_WITH_AS(BsplineVolume(broken, Eigen::MatrixXd::Zero(6 * 5 * 8, 3)),
                       "B-spline volume: knot vector w: interior knot 4 has multiplicity > 3", Error);
  broken = knots;
  broken[1] = {0, 0, 0, 0, 0, 1, 1, 1, 1};
  CHECK_THROWS_WITH_AS(BsplineVolume(broken, Eigen::MatrixXd::Zero(6 * 5 * 7, 3)),
                       "B-spline volume: knot vector v has an end knot of multiplicity > 4", Error);
  CHECK_THROWS_WITH_AS(BsplineVolume(knots, Eigen::MatrixXd::Zero(10, 3)),
                       "B-spline volume: 10 control points given, knot vectors need 210", Error);
  CHECK_THROWS_WITH_AS(BsplineVolume(knots, Eigen::MatrixXd::Zero(210, 5)),
                       "B-spline volume: control point dimension 5 is not in 1..4", Error);
  Eigen::MatrixXd nan_points = points;
  nan_points(17, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH_AS(BsplineVolume(knots, nan_points), "B-spline volume: control point 17 is not finite", Error);
  const BsplineVolume volume(knots, points);
  CHECK_THROWS_WITH_AS(volume.evaluate({0.5, 0.0, 1.5}),
                       "B-spline volume: parameter w = 1.500000 is outside the domain [0.000000, 1.000000]", Error);
  CHECK_THROWS_AS(volume.evaluate({std::nan(""), 0.0, 0.5}), Error);
}
