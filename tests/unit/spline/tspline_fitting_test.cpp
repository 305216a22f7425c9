// SPDX-License-Identifier: MIT
#include "core/spline/tspline_fitting.h"

#include <random>

#include <doctest/doctest.h>

#include "core/spline/bspline_volume.h"

using namespace volspline;

namespace {

spline::BsplineVolume fitting_random_volume(int cells, std::uint64_t seed) {
  std::vector<double> grid(cells + 1);
  for (int i = 0; i <= cells; ++i) grid[i] = double(i) / cells;
  const std::vector<double> knots = spline::boundary_restricted_knots(grid);
  const int n = cells + 3;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  Eigen::MatrixXd points(n * n * n, 3);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double u = double(i) / (n - 1), v = double(j) / (n - 1), w = double(k) / (n - 1);
        points.row(i + n * (j + n * k)) << 2 * u + noise(rng), v + w * w + noise(rng), w + 0.2 * u * v + noise(rng);
      }
  return spline::BsplineVolume({knots, knots, knots}, points);
}

Eigen::MatrixX3d random_parameters(int m, std::uint64_t seed, bool boundary) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::MatrixX3d uvw(m, 3);
  for (int s = 0; s < m; ++s) {
    uvw.row(s) << u(rng), u(rng), u(rng);
    if (boundary) uvw(s, s % 3) = (s / 3) % 2;
  }
  return uvw;
}

}  // namespace

TEST_CASE("a sampled trivariate B-spline is recovered by the least-squares fit") {
  const spline::BsplineVolume volume = fitting_random_volume(3, 11);
  const spline::TSpline truth = spline::from_bspline_volume(volume);
  const Eigen::MatrixX3d uvw = random_parameters(3000, 5, false);
  const Eigen::MatrixX3d xyz = truth.evaluate_batch(uvw);
  spline::TSpline fitted = truth;
  fitted.set_points(Eigen::MatrixXd::Zero(truth.num_functions(), 3));
  spline::TSplineFitOptions options;
  options.smoothing = 0.0;
  options.regularization = 1e-12;  // only to keep the system SPD; bias ~1e-12
  const auto report = spline::fit_tspline(fitted, uvw, xyz, Eigen::MatrixX3d::Zero(truth.num_functions(), 3), options);
  CHECK(report.converged);
  // Tolerance: CG residual 1e-10 on a well-conditioned normal matrix plus the tiny bias.
  CHECK((fitted.points() - truth.points()).cwiseAbs().maxCoeff() < 1e-6);
}

TEST_CASE("the local fit recovers the free control points and leaves the others alone") {
  const spline::BsplineVolume volume = fitting_random_volume(3, 13);
  const spline::TSpline truth = spline::from_bspline_volume(volume);
  const Eigen::MatrixX3d uvw = random_parameters(3000, 7, false);
  const Eigen::MatrixX3d xyz = truth.evaluate_batch(uvw);
  spline::TSpline fitted = truth;
  Eigen::MatrixXd start = truth.points();
  std::vector<int> free_functions;
  for (int i = 0; i < truth.num_functions(); i += 3) {
    free_functions.push_back(i);
    start.row(i).setZero();
  }
  fitted.set_points(start);
  spline::TSplineFitOptions options;
  options.smoothing = 0.0;
  options.regularization = 1e-12;
  const auto report = spline::fit_tspline_local(fitted, uvw, xyz, start, free_functions, options);
  CHECK(report.converged);
  CHECK(report.unknowns == static_cast<int>(free_functions.size()));
  // The fixed control points are the true ones, so the free ones are recovered exactly (CG).
  CHECK((fitted.points() - truth.points()).cwiseAbs().maxCoeff() < 1e-6);
  for (int i = 1; i < truth.num_functions(); i += 3) CHECK(fitted.points().row(i) == truth.points().row(i));
}

TEST_CASE("boundary blending functions are those with 4 equal end knots") {
  const Eigen::Vector3d lo(0, 0, 0), hi(1, 1, 1);
  spline::BlendingKnots inner = {{{0, 0.25, 0.5, 0.75, 1}, {0, 0.25, 0.5, 0.75, 1}, {0, 0.25, 0.5, 0.75, 1}}};
  CHECK_FALSE(spline::touches_exposed_face(inner, lo, hi, polycube::CubeFaceSet::all()));
  spline::BlendingKnots left = inner;
  left[1] = {0, 0, 0, 0, 0.25};
  CHECK(spline::touches_exposed_face(left, lo, hi, polycube::CubeFaceSet::all()));
  spline::BlendingKnots right = inner;
  right[2] = {0.5, 1, 1, 1, 1};
  CHECK(spline::touches_exposed_face(right, lo, hi, polycube::CubeFaceSet::all()));
  spline::BlendingKnots almost = inner;
  almost[0] = {0, 0, 0, 0.25, 0.5};
  CHECK_FALSE(spline::touches_exposed_face(almost, lo, hi, polycube::CubeFaceSet::all()));
  // Only the exposed faces count: `left` touches face 2 (v = 0), `right` face 5 (w = 1).
  const polycube::CubeFaceSet glued_v0 = polycube::CubeFaceSet::all().without(2);
  CHECK_FALSE(spline::touches_exposed_face(left, lo, hi, glued_v0));
  CHECK(spline::touches_exposed_face(right, lo, hi, glued_v0));
  CHECK_FALSE(spline::touches_exposed_face(right, lo, hi, polycube::CubeFaceSet().with(4)));
  CHECK(spline::touches_exposed_face(right, lo, hi, polycube::CubeFaceSet().with(5)));
}

TEST_CASE("the meshless fit recovers the boundary from surface samples and fills the interior") {
  // Target: an affine map. Its boundary is fitted exactly from surface samples (Eq. 4.4), and an
  // affine F has zero discrete Laplacian (Eq. 4.7), so the interior is affine too.
  const spline::BsplineVolume volume = fitting_random_volume(2, 3);
  spline::TSpline ts = spline::from_bspline_volume(volume);
  const Eigen::Matrix3d a = (Eigen::Matrix3d() << 2, 0.1, 0, 0, 1, 0.3, 0.2, 0, 1.5).finished();
  const Eigen::MatrixX3d uvw = random_parameters(2000, 9, true);
  const Eigen::MatrixX3d xyz = uvw * a.transpose();
  ts.set_points(Eigen::MatrixXd::Zero(ts.num_functions(), 3));
  spline::TSplineFitOptions options;
  options.regularization = 1e-12;
  const auto report = spline::fit_tspline_meshless(ts, uvw, xyz, Eigen::MatrixX3d::Zero(ts.num_functions(), 3), options);
  CHECK(report.converged);
  const Eigen::MatrixX3d inside = random_parameters(200, 4, false);
  const Eigen::MatrixXd f = ts.evaluate_batch(inside);
  // Tolerance: CG residuals of two solves.
  CHECK((f - inside * a.transpose()).cwiseAbs().maxCoeff() < 1e-6);
}

TEST_CASE("samples on knot lines and the domain's end faces, with fairing, recover a linear map") {
  // A linear map has zero discrete Laplacian and is reproduced by the splines, so it minimizes
  // the faired least squares exactly; samples on the cell faces (including the closed last
  // cell at u = 1) check that the per-cell assembly puts each sample in the cell of basis_at.
  std::vector<double> grid = {0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0};
  const std::vector<double> knots = spline::boundary_restricted_knots(grid);
  const int n = static_cast<int>(knots.size()) - 4;
  Eigen::Matrix3d a;
  a << 2.0, 0.3, 0.0, -0.1, 1.0, 0.2, 0.0, 0.4, 1.5;
  Eigen::MatrixXd points(n * n * n, 3);
  auto greville = [&](int i) { return (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0; };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        points.row(i + n * (j + n * k)) = (a * Eigen::Vector3d(greville(i), greville(j), greville(k))).transpose();
  const spline::TSpline truth = spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points));
  Eigen::MatrixX3d uvw(7 * 7 * 7, 3);
  for (int k = 0, s = 0; k < 7; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 7; ++i) uvw.row(s++) << i / 6.0, j / 6.0, k / 6.0;
  const Eigen::MatrixX3d xyz = truth.evaluate_batch(uvw);
  spline::TSpline fitted = truth;
  fitted.set_points(Eigen::MatrixXd::Zero(truth.num_functions(), 3));
  spline::TSplineFitOptions options;
  options.smoothing = 1e-2;
  options.regularization = 1e-12;
  const auto report = spline::fit_tspline(fitted, uvw, xyz, Eigen::MatrixX3d::Zero(truth.num_functions(), 3), options);
  CHECK(report.converged);
  // Tolerance: CG residual 1e-10 relative on a well-conditioned system plus the 1e-12 bias.
  CHECK((fitted.evaluate_batch(uvw) - xyz).cwiseAbs().maxCoeff() < 1e-6);
  CHECK((fitted.points() - truth.points()).cwiseAbs().maxCoeff() < 1e-6);
}
