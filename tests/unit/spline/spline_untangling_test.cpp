// SPDX-License-Identifier: MIT
#include "core/spline/spline_untangling.h"

#include <doctest/doctest.h>

#include <algorithm>

#include <Eigen/LU>

#include "core/spline/bspline_volume.h"
#include "core/spline/tspline_fitting.h"
#include "tests/unit/spline/identity_test_volume.h"

using namespace volspline;

namespace {

int untangling_negative_points(const spline::TSpline& ts, int l) {
  int count = 0;
  for (int k = 1; k < l; ++k)
    for (int j = 1; j < l; ++j)
      for (int i = 1; i < l; ++i)
        if (ts.jacobian(Eigen::Vector3d(i, j, k) / l).determinant() <= 0.0) ++count;
  return count;
}

// The centres of the 5×5×5 cells of the unit cube: samples of the identity inside the domain.
Eigen::MatrixX3d cell_centres_5() {
  Eigen::MatrixX3d uvw(5 * 5 * 5, 3);
  for (int s = 0; s < 125; ++s) uvw.row(s) = Eigen::RowVector3d(s % 5 + 0.5, s / 5 % 5 + 0.5, s / 25 + 0.5) / 5.0;
  return uvw;
}

// Every function touching the boundary (all six faces exposed) keeps its control point from
// `points`: the untangler moves interior control points only.
void check_boundary_points_kept(const spline::TSpline& ts, const Eigen::MatrixXd& points) {
  const Eigen::Vector3d lo = ts.domain_min(), hi = ts.domain_max();
  for (int i = 0; i < ts.num_functions(); ++i)
    if (spline::touches_exposed_face(ts.knots()[i], lo, hi, polycube::CubeFaceSet::all())) CHECK(ts.points().row(i) == points.row(i));
}

}  // namespace

TEST_CASE("spline untangling unfolds a near-boundary fold, keeps the boundary and the identity samples") {
  spline::TSpline ts = test::identity_test_volume();
  // Push the second-row control point (1, 3, 3) (zero on the boundary, so interior) past the
  // fourth row (x 0.083 → 1.583): ∂F/∂u < 0 behind it, between the boundary and the middle.
  Eigen::MatrixXd points = ts.points();
  const int id = 1 + 7 * (3 + 7 * 3);
  points(id, 0) += 1.5;
  ts.set_points(points);
  REQUIRE(untangling_negative_points(ts, 16) > 0);
  const Eigen::MatrixX3d uvw = cell_centres_5();
  spline::SplineUntangleOptions options;
  options.lattice = 16;
  options.seed_stride = 1;
  options.energy_stride = 1;
  options.nodes_per_knot_interval = 0;  // the scan is then exactly the j/16 lattice checked below
  options.boundary_layers.clear();
  const spline::SplineUntangleResult report = spline::untangle_spline(ts, uvw, uvw, options);
  CHECK(report.initial_negative > 0);
  CHECK(report.final_negative == 0);
  CHECK(report.final_min_scaled > 0.0);
  CHECK(report.free_functions > 0);
  CHECK(untangling_negative_points(ts, 16) == 0);
  // The report's check comes from the Jacobians the untangler tracks (initial J plus the moved
  // control points' terms): it must agree with the moved spline's own Jacobians.
  double min_scaled = 1.0;
  for (int k = 1; k < 16; ++k)
    for (int j = 1; j < 16; ++j)
      for (int i = 1; i < 16; ++i) {
        const Eigen::Matrix3d jac = ts.jacobian(Eigen::Vector3d(i, j, k) / 16);
        min_scaled = std::min(min_scaled, jac.determinant() / (jac.col(0).norm() * jac.col(1).norm() * jac.col(2).norm()));
      }
  // Rounding only: the two sums add the same terms in another order.
  CHECK(report.final_min_scaled == doctest::Approx(min_scaled).epsilon(1e-9));
  check_boundary_points_kept(ts, points);
}

TEST_CASE("spline untangling on the cell-centre energy nodes unfolds the fold; the moved spline equals a fresh build") {
  spline::TSpline ts = test::identity_test_volume();
  Eigen::MatrixXd points = ts.points();
  points(1 + 7 * (3 + 7 * 3), 0) += 1.5;  // the fold of the test above
  ts.set_points(points);
  const Eigen::MatrixX3d uvw = cell_centres_5();
  spline::SplineUntangleOptions options;
  options.lattice = 16;  // seed_stride 2 and energy_stride 2: the 8³ cell centres of the 16 lattice
  options.nodes_per_knot_interval = 0;
  options.boundary_layers.clear();
  const spline::SplineUntangleResult report = spline::untangle_spline(ts, uvw, uvw, options);
  CHECK(report.scanned == 8 * 8 * 8);
  CHECK(report.initial_negative > 0);
  CHECK(report.final_negative == 0);
  CHECK(report.points <= 8 * 8 * 8);  // the energy holds only the scanned nodes
  CHECK(report.final_min_scaled > 0.0);
  // set_points after the untangling updates the cell polynomials by the moved points' changes
  // only (few points moved): a spline built afresh from the same points agrees to rounding.
  const spline::TSpline fresh(ts.knots(), ts.weights(), ts.points());
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) {
        const Eigen::Vector3d p = Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) / 8.0;
        // Rounding of values of size 1: the update adds the changes, the build sums the terms.
        CHECK((ts.evaluate(p) - fresh.evaluate(p)).norm() < 1e-12);
        CHECK((ts.jacobian(p) - fresh.jacobian(p)).norm() < 1e-11);
        CHECK(fresh.jacobian(p).determinant() > 0.0);
      }
}

TEST_CASE("spline untangling leaves a valid map alone") {
  spline::TSpline ts = test::identity_test_volume();
  const Eigen::MatrixXd before = ts.points();
  const spline::SplineUntangleResult report = spline::untangle_spline(ts, Eigen::MatrixX3d(0, 3), Eigen::MatrixX3d(0, 3));
  // Per axis 6 nodes in each of the 4 knot intervals (one per 2/48) and 2 boundary layers per end.
  CHECK(report.scanned == 28 * 28 * 28);
  CHECK(report.seeds == 0);
  CHECK(report.free_functions == 0);
  CHECK(ts.points() == before);
}

namespace {

// det J ≤ 0 count over points the untangler never holds: the cell centres of a 20³ lattice
// (odd j/40) and 32² points per face at 1/1000 inside.
int unseen_negative_points(const spline::TSpline& ts) {
  int count = 0;
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i)
        if (ts.jacobian(Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) / 20.0).determinant() <= 0.0) ++count;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side)
      for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 32; ++i) {
          Eigen::Vector3d p;
          p(a) = side ? 1.0 - 1e-3 : 1e-3;
          p((a + 1) % 3) = (i + 0.5) / 32.0;
          p((a + 2) % 3) = (j + 0.5) / 32.0;
          if (ts.jacobian(p).determinant() <= 0.0) ++count;
        }
  return count;
}

}  // namespace

TEST_CASE("spline untangling unfolds a fold at a face (normal derivative outward) at points it never held") {
  spline::TSpline ts = test::identity_test_volume();
  // The second-layer point (1, 3, 3) (zero on the face u = 0, so interior) moved past the face:
  // x 0.083 → −0.3, so ∂F/∂u points out of the solid at the face's middle; the surface itself
  // (the boundary points) stays as it is.
  Eigen::MatrixXd points = ts.points();
  points(1 + 7 * (3 + 7 * 3), 0) = -0.3;
  ts.set_points(points);
  // ∂x/∂u at (0, ½, ½) = 12·(−0.3·(2/3)² + 0.083·(1 − (2/3)²)) < 0 (2/3: the middle function at ½).
  REQUIRE(ts.jacobian(Eigen::Vector3d(0.0, 0.5, 0.5)).determinant() < 0.0);
  const int folded = unseen_negative_points(ts);
  REQUIRE(folded > 0);
  const Eigen::MatrixX3d uvw = cell_centres_5();
  spline::SplineUntangleOptions options;
  options.lattice = 16;
  SUBCASE("without boundary layers the cell-centre nodes (first at 1/16) miss most of it") {
    spline::TSpline plain = ts;
    options.boundary_layers.clear();
    options.check_per_interval = 0;
    options.passes = 3;
    options.polish_rounds = 0;
    options.certificate_rounds = 0;
    spline::untangle_spline(plain, uvw, uvw, options);
    CHECK(unseen_negative_points(plain) > 0);
  }
  SUBCASE("without boundary layers the dense check's points (first at 1/24) catch what the nodes miss") {
    options.boundary_layers.clear();
    REQUIRE(options.check_per_interval == 3);  // the default
    options.passes = 3;                        // the check runs between passes
    options.polish_rounds = 0;
    const spline::SplineUntangleResult report = spline::untangle_spline(ts, uvw, uvw, options);
    CHECK(report.check_points > 0);  // the first check found bad points between the nodes
    CHECK(unseen_negative_points(ts) == 0);
    check_boundary_points_kept(ts, points);
  }
  SUBCASE("the polish holds the finest lattice that one pass on coarse nodes leaves folded") {
    // One pass on 2 nodes per knot interval (no boundary layers, no check): the fold stays at
    // points of the polish lattice (per axis the centres of `lattice` = 16 parts).
    options.boundary_layers.clear();
    options.check_per_interval = 0;
    options.passes = 1;
    auto lattice_folded = [](const spline::TSpline& s) {
      int count = 0;
      for (int k = 0; k < 16; ++k)
        for (int j = 0; j < 16; ++j)
          for (int i = 0; i < 16; ++i)
            if (s.jacobian(Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) / 16.0).determinant() <= 0.0) ++count;
      return count;
    };
    options.certificate_rounds = 0;
    spline::TSpline unpolished = ts;
    options.polish_rounds = 0;
    spline::untangle_spline(unpolished, uvw, uvw, options);
    CHECK(lattice_folded(unpolished) > 0);
    options.polish_rounds = 8;
    const spline::SplineUntangleResult report = spline::untangle_spline(ts, uvw, uvw, options);
    CHECK(report.polish_passes > 0);
    CHECK(report.polish_folded == 0);
    CHECK(lattice_folded(ts) == 0);
    check_boundary_points_kept(ts, points);
    // A pass that unfolds at least polish_min_unfolded of its seeds is kept: the same points (to
    // rounding: a copy whose points are set again does not repeat the last bits).
    spline::TSpline strict = ts;
    strict.set_points(points);
    options.polish_min_unfolded = 0.5;
    const spline::SplineUntangleResult strict_report = spline::untangle_spline(strict, uvw, uvw, options);
    CHECK(strict_report.polish_folded == 0);
    CHECK(strict_report.polish_passes == report.polish_passes);
    CHECK((strict.points() - ts.points()).cwiseAbs().maxCoeff() < 1e-12);
  }
  SUBCASE("with them it is gone everywhere the check looks") {
    REQUIRE(options.boundary_layers.size() == 2);  // the defaults: 1/4 and 1/2 of the first node's depth
    const spline::SplineUntangleResult report = spline::untangle_spline(ts, uvw, uvw, options);
    CHECK(report.initial_negative > 0);
    CHECK(report.final_negative == 0);
    CHECK(unseen_negative_points(ts) == 0);
    CHECK(ts.jacobian(Eigen::Vector3d(0.0, 0.5, 0.5)).determinant() > 0.0);
    check_boundary_points_kept(ts, points);
  }
}

TEST_CASE("spline untangling with a boundary layer on the faces themselves leaves out the cuboid edges") {
  spline::TSpline ts = test::identity_test_volume();
  Eigen::MatrixXd points = ts.points();
  points(1 + 7 * (3 + 7 * 3), 0) = -0.3;  // the face fold of the test above
  ts.set_points(points);
  spline::SplineUntangleOptions options;
  options.lattice = 16;
  options.boundary_layers = {0.0, 0.5};
  const spline::SplineUntangleResult report = spline::untangle_spline(ts, Eigen::MatrixX3d(0, 3), Eigen::MatrixX3d(0, 3), options);
  // Per axis 2 nodes in each of the 4 knot intervals and 2 layers per end; the 3·2²·10 + 8
  // nodes on two or three faces (edges, where a smooth surface has det J = 0) are not scanned.
  CHECK(report.scanned == 12 * 12 * 12 - 3 * 4 * 10 - 8);
  CHECK(report.final_negative == 0);
  CHECK(unseen_negative_points(ts) == 0);
}

TEST_CASE("spline untangling on a region: folds outside it stay, functions reaching out of it stay") {
  spline::TSpline folded = test::identity_test_volume();
  Eigen::MatrixXd points = folded.points();
  points(1 + 7 * (3 + 7 * 3), 0) += 1.5;  // the fold of the first test, near u = 0
  folded.set_points(points);
  const Eigen::MatrixX3d uvw = cell_centres_5();
  spline::SplineUntangleOptions options;
  options.lattice = 16;
  options.seed_stride = 1;
  options.energy_stride = 1;
  options.nodes_per_knot_interval = 0;
  options.boundary_layers.clear();
  // A region away from the fold: nothing to see, nothing moves.
  spline::TSpline far = folded;
  options.region = {{Eigen::Vector3d(0.5, 0.0, 0.0), Eigen::Vector3d(1.0, 1.0, 1.0)}};
  const spline::SplineUntangleResult untouched = spline::untangle_spline(far, uvw, uvw, options);
  CHECK(untouched.initial_negative == 0);
  CHECK(far.points() == points);
  // A region holding it: unfolded inside; functions whose support leaves [0, 0.75] in u stay.
  spline::TSpline near = folded;
  options.region = {{Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(0.75, 1.0, 1.0)}};
  const spline::SplineUntangleResult fixed = spline::untangle_spline(near, uvw, uvw, options);
  CHECK(fixed.initial_negative > 0);
  CHECK(fixed.final_negative == 0);
  int negative = 0;
  for (int k = 1; k < 16; ++k)
    for (int j = 1; j < 16; ++j)
      for (int i = 1; i < 12; ++i)
        negative += near.jacobian(Eigen::Vector3d(i, j, k) / 16).determinant() <= 0.0;
  CHECK(negative == 0);
  for (int f = 0; f < near.num_functions(); ++f)
    if (near.knots()[f][0][4] > 0.75) CHECK(near.points().row(f) == points.row(f));
}
