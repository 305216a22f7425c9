// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/common/error.h"
#include "core/spline/bezier_extraction.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/edge_crease.h"
#include "core/spline/jacobian_certificate.h"
#include "core/spline/tspline.h"

using volspline::spline::BsplineVolume;
using volspline::spline::certify_bezier_cell;
using volspline::spline::certify_jacobian;
using volspline::spline::convex_edge_creases;
using volspline::spline::edge_lower_bound_rel;
using volspline::spline::EdgeCreaseOptions;
using volspline::spline::EdgeCreaseResult;
using volspline::spline::extract_bezier_cell;
using volspline::spline::from_bspline_volume;
using volspline::spline::JacobianCellStatus;
using volspline::spline::JacobianCertificate;
using volspline::spline::TSpline;
using volspline::spline::UncertifiedCell;

namespace {

inline int net(int i, int j, int k) { return i + 4 * j + 16 * k; }

// One Bézier cell on [0,1]³: the identity net (i/3, j/3, k/3) with its edge row (3, 3, k) moved
// to (5/6 − e, 5/6 − e, k/3). For e = 0 the points (2, 3, k), (3, 3, k), (3, 2, k) lie on the line
// x + y = 5/3: the faces u = 1 and v = 1 meet at a flat angle along the edge u = v = 1 and det J
// = 0 there. On that edge J_u = 3(P33 − P23), J_v = 3(P33 − P32), J_w = (0, 0, 1), so
// det J = 9·((1/6 − e)² − (1/6 + e)²) = −6e: e > 0 is a concave crease, e < 0 a convex one.
TSpline cut_corner_cell(double e) {
  const std::vector<double> bezier = {0, 0, 0, 0, 1, 1, 1, 1};
  Eigen::MatrixXd points(64, 3);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) points.row(net(i, j, k)) << i / 3.0, j / 3.0, k / 3.0;
  for (int k = 0; k < 4; ++k) points.row(net(3, 3, k)) << 5.0 / 6.0 - e, 5.0 / 6.0 - e, k / 3.0;
  return from_bspline_volume(BsplineVolume({bezier, bezier, bezier}, points));
}

}  // namespace

TEST_CASE("edge crease: a slightly concave crease on a cuboid edge is tilted convex and certified") {
  TSpline spline = cut_corner_cell(0.01);
  const JacobianCertificate before = certify_jacobian(spline);
  REQUIRE(before.uncertified.size() == 1);
  CHECK(before.uncertified[0].bound.status == JacobianCellStatus::Negative);
  // det J on the edge u = v = 1 (along w: t = 2, a = u high, b = v high) is −6e < 0.
  CHECK(edge_lower_bound_rel(spline, 0, 2, true, true) < -1e-3);
  const Eigen::MatrixXd old_points = spline.points();

  const EdgeCreaseResult result = convex_edge_creases(spline, before.uncertified);
  CHECK(result.edges == 1);
  CHECK(result.fixed == 1);
  const JacobianCertificate after = certify_jacobian(spline);
  CHECK(after.jacobian_certified_fraction == 1.0);
  // The crease is convex now: det J > 0 along the whole edge (the certificate subdivides where
  // the edge's own coefficients are still slightly negative).
  for (int q = 0; q <= 100; ++q) CHECK(spline.jacobian({1, 1, q / 100.0}).determinant() > 0.0);

  // Only the rows next to the edge move: (2, 3, k) in face v = 1 and (3, 2, k) in face u = 1.
  std::vector<int> expected;
  for (int k = 0; k < 4; ++k) {
    expected.push_back(net(3, 2, k));
    expected.push_back(net(2, 3, k));
  }
  std::sort(expected.begin(), expected.end());
  CHECK(result.moved == expected);
  for (int f = 0; f < 64; ++f) {
    const Eigen::Vector3d d = (spline.points().row(f) - old_points.row(f)).transpose();
    if (!std::binary_search(expected.begin(), expected.end(), f)) {
      CHECK(d.norm() == 0.0);
      continue;
    }
    // Towards the inside (the outward normal at the edge is (1, 1, 0)/√2), by the order of e:
    // far below the control spacing 1/3.
    CHECK(d.dot(Eigen::Vector3d(1, 1, 0)) < 0.0);
    CHECK(d.norm() > 0.001);
    CHECK(d.norm() < 0.05);
    CHECK(d.norm() <= result.max_displacement * (1 + 1e-12));
  }
  // The edge curve itself stays: F on u = v = 1 is unchanged.
  const TSpline original = cut_corner_cell(0.01);
  for (double w : {0.0, 0.3, 0.7, 1.0})
    CHECK((spline.evaluate({1, 1, w}) - original.evaluate({1, 1, w})).norm() <= 1e-14);
}

TEST_CASE("edge crease: a flat crease is certified and left untouched") {
  TSpline spline = cut_corner_cell(0.0);
  const JacobianCertificate certificate = certify_jacobian(spline);
  CHECK(certificate.jacobian_certified_fraction == 1.0);
  // On the edge det J is 0 to rounding: the coefficients there are within τ.
  CHECK(std::abs(edge_lower_bound_rel(spline, 0, 2, true, true)) <= 1e-12);
  // Listed anyway (as a caller might), the cell is not moved: it is certified.
  UncertifiedCell listed;
  listed.cell = 0;
  listed.uvw_max = Eigen::Vector3d::Ones();
  listed.bound = certify_bezier_cell(extract_bezier_cell(spline, 0), {});
  const Eigen::MatrixXd points = spline.points();
  const EdgeCreaseResult result = convex_edge_creases(spline, {listed});
  CHECK(result.edges == 0);
  CHECK(result.moved.empty());
  CHECK(spline.points() == points);
}

TEST_CASE("edge crease: an edge between a covered face and an exposed one is no crease") {
  TSpline spline = cut_corner_cell(0.01);
  const JacobianCertificate certificate = certify_jacobian(spline);
  EdgeCreaseOptions options;
  options.exposed_faces = volspline::polycube::CubeFaceSet::all().without(1);  // u = 1 glued
  const Eigen::MatrixXd points = spline.points();
  const EdgeCreaseResult result = convex_edge_creases(spline, certificate.uncertified, options);
  CHECK(result.moved.empty());
  CHECK(spline.points() == points);
}

TEST_CASE("edge crease: bad options and dimensions are rejected") {
  TSpline spline = cut_corner_cell(0.01);
  const JacobianCertificate certificate = certify_jacobian(spline);
  EdgeCreaseOptions options;
  options.margin = 0.0;
  CHECK_THROWS_WITH_AS(convex_edge_creases(spline, certificate.uncertified, options),
                       doctest::Contains("margin"), volspline::Error);
  options = {};
  options.tries = 0;
  CHECK_THROWS_WITH_AS(convex_edge_creases(spline, certificate.uncertified, options),
                       doctest::Contains("tries"), volspline::Error);
  options = {};
  options.edge_samples = 1;
  CHECK_THROWS_WITH_AS(convex_edge_creases(spline, certificate.uncertified, options),
                       doctest::Contains("edge_samples"), volspline::Error);
  const std::vector<double> bezier = {0, 0, 0, 0, 1, 1, 1, 1};
  TSpline scalar = from_bspline_volume(BsplineVolume({bezier, bezier, bezier}, Eigen::MatrixXd::Ones(64, 1)));
  CHECK_THROWS_WITH_AS(convex_edge_creases(scalar, {}), doctest::Contains("dimension 1"), volspline::Error);
}
