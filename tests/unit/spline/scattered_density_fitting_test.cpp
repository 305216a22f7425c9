// SPDX-License-Identifier: MIT
#include "core/spline/scattered_density_fitting.h"

#include <cstdint>
#include <vector>

#include <Eigen/Cholesky>
#include <doctest/doctest.h>

#include "core/spline/bspline_volume.h"
#include "core/spline/hierarchical_refinement.h"

using namespace volspline;

namespace {

double scattered_cubic(const Eigen::Vector3d& p) {
  return 0.5 + p.x() * p.x() * p.x() - 2.0 * p.x() * p.y() + 0.7 * p.y() * p.y() * p.z() + p.x() * p.y() * p.z() * p.z();
}

// A 3×3×3-cell cubic B-spline over [0, 1]³ with two cells split: a T-spline with T-junctions
// and cells of different function lists.
spline::TSpline scattered_refined_spline(spline::RefinementGrid& grid, int dimension) {
  std::array<std::vector<double>, 3> knots;
  for (auto& k : knots) k = {0, 0, 0, 0, 1.0 / 3, 2.0 / 3, 1, 1, 1, 1};
  const spline::TSpline coarse = spline::from_bspline_volume(
      spline::BsplineVolume(knots, Eigen::MatrixXd::Zero(216, dimension)), spline::TSplineAcceleration::FunctionLists);
  return grid.split(coarse, {0, 13}, spline::TSplineAcceleration::FunctionLists);
}

// Deterministic samples: a pseudo-random cloud plus points exactly on knot lines and corners.
Eigen::MatrixX3d scattered_samples() {
  std::vector<Eigen::Vector3d> p;
  std::uint64_t state = 12345;
  auto next = [&]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / static_cast<double>(1ULL << 53);
  };
  for (int s = 0; s < 3000; ++s) p.emplace_back(next(), next(), next());
  for (double a : {0.0, 1.0 / 6, 1.0 / 3, 0.5, 2.0 / 3, 1.0})
    for (double b : {0.0, 1.0 / 3, 1.0})
      for (double c : {0.0, 0.25, 1.0}) p.emplace_back(a, b, c);
  Eigen::MatrixX3d uvw(static_cast<Eigen::Index>(p.size()), 3);
  for (std::size_t s = 0; s < p.size(); ++s) uvw.row(static_cast<Eigen::Index>(s)) = p[s].transpose();
  return uvw;
}

}  // namespace

TEST_CASE("scattered fit on a refined T-spline reproduces a cubic and agrees with a dense solve") {
  spline::RefinementGrid grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {3, 3, 3});
  spline::TSpline s = scattered_refined_spline(grid, 1);
  REQUIRE(s.num_functions() > 216);
  const Eigen::MatrixX3d uvw = scattered_samples();
  Eigen::MatrixXd targets(uvw.rows(), 1);
  for (Eigen::Index r = 0; r < uvw.rows(); ++r) targets(r, 0) = scattered_cubic(uvw.row(r).transpose());
  spline::GridFitOptions options;
  options.tolerance = 1e-13;
  options.regularization = 1e-14;  // negligible ridge: the plain least-squares solution
  const spline::ScatteredFitResult report = spline::fit_tspline_scattered(s, uvw, targets, {0}, options);
  CHECK(report.converged);
  CHECK(report.unknowns == s.num_functions());
  double worst = 0.0;
  for (Eigen::Index r = 0; r < uvw.rows(); ++r)
    worst = std::max(worst, std::abs(s.evaluate(uvw.row(r).transpose())(0) - targets(r, 0)));
  CHECK(worst < 1e-8);  // the cubic is in the spline space; 1e-8 for CG at 1e-13 on a Gram matrix
  // Dense normal equations from the blending functions themselves (no grouping, no grid).
  const int n = s.num_functions();
  Eigen::MatrixXd m(uvw.rows(), n);
  for (Eigen::Index r = 0; r < uvw.rows(); ++r)
    for (int i = 0; i < n; ++i) m(r, i) = s.weights()(i) * s.blending_function(i, uvw.row(r).transpose());
  const Eigen::MatrixXd gram = m.transpose() * m;
  const Eigen::VectorXd dense = gram.ldlt().solve(m.transpose() * targets.col(0));
  // Refined T-splines may have linearly dependent functions, so compare fitted values.
  CHECK((m * s.points().col(0) - m * dense).cwiseAbs().maxCoeff() < 1e-8);
  CHECK(report.normal_nonzeros <= static_cast<long long>(n) * n);
}

TEST_CASE("adaptive scattered fit: geometry from the last normal matrix reproduces an affine map") {
  const int n = 9;
  Eigen::MatrixX3d uvw(n * n * n, 3);
  Eigen::MatrixXd targets(n * n * n, 4);
  for (int z = 0, v = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x, ++v) {
        const Eigen::Vector3d u(x / (n - 1.0), y / (n - 1.0), z / (n - 1.0));
        uvw.row(v) = u.transpose();
        // Sheared geometry, not the identity guess the geometry solve starts from.
        targets.row(v) << 8.0 * u.x() + 2.0 * u.y(), 8.0 * u.y() - u.z(), 8.0 * u.z() + 0.5 * u.x(),
            (x == 4 && y == 4 && z == 4) ? 100.0 : 0.0;
      }
  spline::AdaptiveDensityOptions options;
  options.max_rms_rel = 1e-14;
  options.max_levels = 2;
  options.max_control_points = 4000;
  options.initial_cells = 2;
  options.min_gain_rate = 0.0;
  options.min_decrease_rel = 0.0;
  options.fit.tolerance = 1e-13;
  options.fit.regularization = 1e-14;
  const spline::ScatteredDensityResult r = spline::fit_scattered_adaptive(uvw, targets, {n, n, n}, options);
  REQUIRE(r.levels.size() >= 2);
  CHECK(r.levels.back().rms_rel < r.levels.front().rms_rel);
  CHECK(r.levels.back().control_points == r.spline.num_functions());
  for (const Eigen::Vector3d& u : {Eigen::Vector3d(0.3, 0.6, 0.9), Eigen::Vector3d(0.5, 0.5, 0.5), Eigen::Vector3d(1, 0, 1)}) {
    const Eigen::VectorXd f = r.spline.evaluate(u);
    CHECK(f(0) == doctest::Approx(8.0 * u.x() + 2.0 * u.y()).epsilon(1e-8));
    CHECK(f(1) == doctest::Approx(8.0 * u.y() - u.z()).epsilon(1e-8));
    CHECK(f(2) == doctest::Approx(8.0 * u.z() + 0.5 * u.x()).epsilon(1e-8));
  }
  // The reconstruction is the final spline's density at the samples.
  CHECK(r.reconstruction[100] == doctest::Approx(r.spline.evaluate(uvw.row(100).transpose())(3)).epsilon(1e-12));
}

TEST_CASE("the scattered fit gives the same bits for every thread count") {
  // Samples grouped by knot-line cell, several cells sharing a list (the split cells' lines run
  // through their neighbours): the normal matrix, hence the solution, must not depend on threads.
  const Eigen::MatrixX3d uvw = scattered_samples();
  Eigen::MatrixXd targets(uvw.rows(), 1);
  for (Eigen::Index r = 0; r < uvw.rows(); ++r) targets(r, 0) = scattered_cubic(uvw.row(r).transpose());
  Eigen::MatrixXd first;
  for (int threads : {1, 2, 3}) {
    CAPTURE(threads);
    spline::RefinementGrid grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {3, 3, 3});
    spline::TSpline s = scattered_refined_spline(grid, 1);
    spline::GridFitOptions options;
    options.threads = threads;
    const spline::ScatteredFitResult report = spline::fit_tspline_scattered(s, uvw, targets, {0}, options);
    CHECK(report.converged);
    if (threads == 1)
      first = s.points();
    else
      CHECK(s.points() == first);
  }
}
