// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "core/common/error.h"
#include "core/spline/bezier_extraction.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/jacobian_certificate.h"
#include "core/spline/tspline.h"
#include "fold_cell.h"

using volspline::spline::BezierCell;
using volspline::spline::BsplineVolume;
using volspline::spline::certify_bezier_cell;
using volspline::spline::certify_jacobian;
using volspline::spline::extract_bezier_cell;
using volspline::spline::from_bspline_volume;
using volspline::spline::JacobianCellBound;
using volspline::spline::JacobianCellStatus;
using volspline::spline::TSpline;

namespace {

// One Bézier cell on [0,1]³ with control point (i, j, k) = net(i/3, j/3, k/3) (for a map that is
// affine per axis these are its values there).
TSpline single_cell(const std::function<Eigen::Vector3d(double, double, double)>& net) {
  const std::vector<double> bezier = {0, 0, 0, 0, 1, 1, 1, 1};
  Eigen::MatrixXd points(64, 3);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) points.row(i + 4 * j + 16 * k) = net(i / 3.0, j / 3.0, k / 3.0).transpose();
  return from_bspline_volume(BsplineVolume({bezier, bezier, bezier}, points));
}

// The identity on a 5×4×4 uniform grid of [0,1]³ with control points moved by `noise` (uniform
// in ±noise per coordinate, seeded).
TSpline perturbed_identity(double noise, unsigned seed) {
  const std::vector<double> k0 = volspline::spline::boundary_restricted_knots({0, 0.2, 0.4, 0.6, 0.8, 1});
  const std::vector<double> k1 = volspline::spline::boundary_restricted_knots({0, 0.25, 0.5, 0.75, 1});
  std::vector<double> greville[3];
  const std::vector<double>* knots[3] = {&k0, &k1, &k1};
  for (int a = 0; a < 3; ++a)
    for (size_t i = 0; i + 4 < knots[a]->size(); ++i)
      greville[a].push_back(((*knots[a])[i + 1] + (*knots[a])[i + 2] + (*knots[a])[i + 3]) / 3.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-noise, noise);
  const int n0 = int(greville[0].size()), n1 = int(greville[1].size()), n2 = int(greville[2].size());
  Eigen::MatrixXd points(n0 * n1 * n2, 3);
  for (int k = 0; k < n2; ++k)
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n0; ++i)
        points.row(i + n0 * (j + n1 * k)) << greville[0][i] + jitter(rng), greville[1][j] + jitter(rng),
            greville[2][k] + jitter(rng);
  return from_bspline_volume(BsplineVolume({k0, k1, k1}, points));
}

double det_at(const TSpline& spline, const Eigen::Vector3d& uvw) {
  return spline.jacobian(uvw).determinant();
}

// Smallest det J at `samples` random points of the cell and its 8 corners.
double sampled_min(const TSpline& spline, const BezierCell& cell, int samples, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double lowest = 1e300;
  for (int n = 0; n < samples + 8; ++n) {
    Eigen::Vector3d s(unit(rng), unit(rng), unit(rng));
    if (n < 8) s = Eigen::Vector3d(n & 1, (n >> 1) & 1, (n >> 2) & 1);
    const Eigen::Vector3d uvw = cell.uvw_min + s.cwiseProduct(cell.uvw_max - cell.uvw_min);
    double value[3], jacobian[9];
    volspline::spline::evaluate_bezier_cell(cell, s, value, jacobian);
    lowest = std::min(lowest, Eigen::Map<Eigen::Matrix3d>(jacobian).determinant());
    (void)uvw;
  }
  return lowest;
}

}  // namespace

TEST_CASE("det J coefficients of the identity and of a polynomial map are exact") {
  const TSpline identity = single_cell([](double u, double v, double w) { return Eigen::Vector3d(u, v, w); });
  double c[volspline::spline::kJacobianCoefficients], bound = 0;
  volspline::spline::jacobian_determinant_bernstein(extract_bezier_cell(identity, 0), c, &bound);
  for (double x : c) CHECK(x == doctest::Approx(1.0).epsilon(1e-14));
  CHECK(bound == doctest::Approx(1.0));
  // F = (u, v, u v w): det J = u v, whose Bernstein coefficients are i j / 64.
  const TSpline product = single_cell([](double u, double v, double w) { return Eigen::Vector3d(u, v, u * v * w); });
  volspline::spline::jacobian_determinant_bernstein(extract_bezier_cell(product, 0), c, &bound);
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 9; ++i) CHECK(c[i + 9 * j + 81 * k] == doctest::Approx(i * j / 64.0).epsilon(1e-13));
}

TEST_CASE("a map that is degenerate along a cuboid edge but never below is certified") {
  // det J = u v: 0 on the faces u = 0 and v = 0 (so on their edge), positive inside.
  const TSpline edge = single_cell([](double u, double v, double w) { return Eigen::Vector3d(u, v, u * v * w); });
  const JacobianCellBound b = certify_bezier_cell(extract_bezier_cell(edge, 0), {});
  CHECK(b.status == JacobianCellStatus::Certified);
  CHECK(b.det_j_lower_bound == doctest::Approx(0.0).epsilon(1e-15));
  // det J = u v − 0.01: negative near that edge; the corner value proves the fold.
  const TSpline fold = single_cell(
      [](double u, double v, double w) { return Eigen::Vector3d(u, v, u * v * w - 0.01 * w); });
  const JacobianCellBound f = certify_bezier_cell(extract_bezier_cell(fold, 0), {});
  CHECK(f.status == JacobianCellStatus::Negative);
  CHECK(f.det_j_lower_bound <= -0.01 + 1e-12);
  const volspline::spline::JacobianCertificate all = certify_jacobian(fold);
  CHECK(all.jacobian_certified_fraction == 0.0);
  REQUIRE(all.uncertified.size() == 1);
  CHECK(all.uncertified[0].uvw_max == Eigen::Vector3d(1, 1, 1));
}

TEST_CASE("subdivision certifies cells whose first coefficients are negative") {
  // det J = (u − 1/2)² + 0.003 (x = u³/3 − u²/2 + (1/4 + 0.003) u): positive, but its degree-8
  // Bernstein coefficients (of a degree-2 polynomial elevated) dip below 0 in the middle.
  // Its cubic Bernstein coefficients (c1/3, 2c1/3 + c2/3, c1 + c2 + c3 for c = (0, 0.253, −1/2, 1/3)).
  const double x[4] = {0.0, 0.253 / 3, 2 * 0.253 / 3 - 0.5 / 3, 0.253 - 0.5 + 1.0 / 3};
  const TSpline dip = single_cell(
      [&](double u, double v, double w) { return Eigen::Vector3d(x[int(std::lround(3 * u))], v, w); });
  double c[volspline::spline::kJacobianCoefficients], bound = 0;
  volspline::spline::jacobian_determinant_bernstein(extract_bezier_cell(dip, 0), c, &bound);
  CHECK(*std::min_element(c, c + 729) < 0);
  const JacobianCellBound b = certify_bezier_cell(extract_bezier_cell(dip, 0), {});
  CHECK(b.status == JacobianCellStatus::Certified);
  CHECK(b.leaves > 1);
  CHECK(b.det_j_lower_bound > 0);
  CHECK(b.det_j_lower_bound <= 0.003 + 1e-15);
  volspline::spline::JacobianCertificateOptions shallow;
  shallow.max_depth = 0;
  CHECK(certify_bezier_cell(extract_bezier_cell(dip, 0), shallow).status == JacobianCellStatus::Undecided);
}

TEST_CASE("no sample falls below the certified bound (20 cells of perturbed maps, brute force)") {
  int checked = 0, negative = 0, certified = 0;
  for (unsigned seed = 1; checked < 20; ++seed) {
    const TSpline spline = perturbed_identity(0.09, seed);
    std::mt19937 rng(seed);
    const int c = int(rng() % unsigned(spline.num_cells()));
    const BezierCell cell = extract_bezier_cell(spline, c);
    const JacobianCellBound b = certify_bezier_cell(cell, {});
    const double lowest = sampled_min(spline, cell, 20000, seed);
    CAPTURE(seed);
    CHECK(lowest >= b.det_j_lower_bound - 1e-12);
    if (b.status == JacobianCellStatus::Certified) {
      CHECK(lowest >= -1e-12);
      ++certified;
    }
    if (lowest < 0) {
      CHECK(b.status != JacobianCellStatus::Certified);
      ++negative;
    }
    ++checked;
  }
  CHECK(certified > 0);
  // The bound is tight enough to be useful: the uvw-space bound matches det_at's scale.
  const TSpline spline = perturbed_identity(0.0, 1);
  CHECK(certify_jacobian(spline).det_j_lower_bound_rel == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(det_at(spline, Eigen::Vector3d(0.3, 0.3, 0.3)) == doctest::Approx(1.0));
  MESSAGE("folded cells among the 20: " << negative);
}

TEST_CASE("certify_jacobian rejects a non-geometric spline and bad options") {
  const std::vector<double> bezier = {0, 0, 0, 0, 1, 1, 1, 1};
  const TSpline scalar = from_bspline_volume(BsplineVolume({bezier, bezier, bezier}, Eigen::MatrixXd::Ones(64, 1)));
  CHECK_THROWS_WITH_AS(certify_jacobian(scalar), doctest::Contains("dimension 1"), volspline::Error);
  volspline::spline::JacobianCertificateOptions bad;
  bad.max_depth = 30;
  const TSpline identity = single_cell([](double u, double v, double w) { return Eigen::Vector3d(u, v, w); });
  CHECK_THROWS_WITH_AS(certify_jacobian(identity, bad), doctest::Contains("max_depth"), volspline::Error);
}

TEST_CASE("a certificate cache gives every cell the bound of a fresh certificate after control points move") {
  TSpline spline = perturbed_identity(0.12, 7);
  volspline::spline::JacobianCertificateCache cache;
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  auto same = [](const volspline::spline::JacobianCertificate& a, const volspline::spline::JacobianCertificate& b) {
    REQUIRE(a.cells == b.cells);
    CHECK(a.certified_cells == b.certified_cells);
    CHECK(a.cell_bound_rel == b.cell_bound_rel);
    REQUIRE(a.uncertified.size() == b.uncertified.size());
    for (std::size_t u = 0; u < a.uncertified.size(); ++u) {
      CHECK(a.uncertified[u].cell == b.uncertified[u].cell);
      CHECK(a.uncertified[u].bound.lowest_corner_s == b.uncertified[u].bound.lowest_corner_s);
    }
  };
  same(volspline::spline::certify_jacobian_in_box(spline, lo, hi, {}, 0, &cache), certify_jacobian(spline));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (int round = 0; round < 5; ++round) {
    // A few control points moved far enough to fold cells near them.
    Eigen::MatrixXd points = spline.points();
    for (int m = 0; m < 3; ++m) points.row(static_cast<int>(rng() % points.rows())) += Eigen::RowVector3d(jitter(rng), jitter(rng), jitter(rng));
    spline.set_points(points);
    same(volspline::spline::certify_jacobian_in_box(spline, lo, hi, {}, 0, &cache), certify_jacobian(spline));
  }
  // Other options: nothing stored is reused.
  volspline::spline::JacobianCertificateOptions shallow;
  shallow.max_depth = 1;
  same(volspline::spline::certify_jacobian_in_box(spline, lo, hi, shallow, 0, &cache), certify_jacobian(spline, shallow));
}

TEST_CASE("certify_bezier_cell: a cell whose det J comes within 1e-4 of 0 needs the deeper splits") {
  // det J = (s0 − 0.3)² + (s1 − 0.7)² + (s2 − 0.6)² + 1e-4 > 0: the Bernstein coefficients of a
  // box of width h around the minimum reach about −0.036·h² per axis below the values, so
  // 4 splits per axis (12, the default) leave a negative coefficient and no negative corner; 8
  // per axis (24, a GPC spline's gpc_certificate_options) do not.
  const BezierCell cell = volspline::spline::test::fold_cell(0.3, 0.7, 0.6, -1e-4);
  CHECK(certify_bezier_cell(cell, {}).status == JacobianCellStatus::Undecided);
  volspline::spline::JacobianCertificateOptions options;
  options.max_depth = 24;
  const JacobianCellBound deep = certify_bezier_cell(cell, options);
  CHECK(deep.status == JacobianCellStatus::Certified);
  CHECK(deep.det_j_lower_bound > 0.0);
  CHECK(deep.det_j_lower_bound <= 1e-4);
}
