// SPDX-License-Identifier: MIT
#include "core/spline/density_fitting.h"

#include <cmath>
#include <string>

#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/spline/hierarchical_refinement.h"
#include "core/spline/scattered_density_fitting.h"

using namespace volspline;

namespace {

// A trivariate cubic (degree 3 per axis, so inside every cubic spline space on the grid).
double cubic(double x, double y, double z) {
  return 0.5 + 0.01 * x * x * x - 0.03 * x * y + 0.002 * y * y * z + 0.0004 * x * y * z * z - 0.05 * z;
}

spline::GridSamples cubic_samples(std::array<int, 3> dims) {
  spline::GridSamples s;
  s.dims = dims;
  for (int z = 0; z < dims[2]; ++z)
    for (int y = 0; y < dims[1]; ++y)
      for (int x = 0; x < dims[0]; ++x) s.values.push_back(cubic(x, y, z));
  return s;
}

// A blob on zero background: a Gaussian bump and a step.
spline::GridSamples blob_samples(int n) {
  spline::GridSamples s;
  s.dims = {n, n, n};
  const double c = 0.5 * (n - 1);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double r2 = (x - c) * (x - c) + (y - c) * (y - c) + (z - 0.7 * c) * (z - 0.7 * c);
        s.values.push_back(200.0 * std::exp(-r2 / 8.0) + (x > c && y > c ? 50.0 : 0.0));
      }
  return s;
}

}  // namespace

TEST_CASE("uniform B-spline least squares reproduces a trivariate cubic exactly") {
  const spline::GridSamples s = cubic_samples({12, 10, 9});
  const spline::UniformBsplineFit fit = spline::fit_uniform_bspline(s, {6, 5, 4});
  CHECK(fit.volume.num_control(0) == 6);
  CHECK(fit.error.max_rel < 1e-10);  // direct dense solves: rounding only
  // The volume evaluates like the reconstruction.
  CHECK(fit.volume.evaluate(Eigen::Vector3d(3, 4, 5))(0) == doctest::Approx(cubic(3, 4, 5)).epsilon(1e-10));
}

TEST_CASE("uniform B-spline fit rejects too many control points and too few") {
  const spline::GridSamples s = cubic_samples({6, 6, 6});
  CHECK_THROWS_WITH_AS(spline::fit_uniform_bspline(s, {8, 4, 4}), doctest::Contains("only 6 samples"), Error);
  CHECK_THROWS_WITH_AS(spline::fit_uniform_bspline(s, {3, 4, 4}), doctest::Contains("at least 4"), Error);
}

TEST_CASE("grid fit of a refined T-spline reproduces a trivariate cubic to 1e-9") {
  const spline::GridSamples s = cubic_samples({17, 17, 17});
  spline::AdaptiveDensityOptions options;
  options.max_rms_rel = 1e-14;  // force refinement
  options.max_levels = 2;
  options.initial_cells = 2;
  options.fit.tolerance = 1e-13;
  options.fit.regularization = 1e-14;
  const spline::AdaptiveDensityResult r = spline::fit_density_adaptive(s, options);
  REQUIRE(r.levels.size() >= 2);
  CHECK(r.spline.dimension() == 4);
  CHECK(r.error.max_rel < 1e-9);
  // Geometry X, Y, Z is the identity (Eq. 5.11 with the identity parameterization).
  const Eigen::VectorXd f = r.spline.evaluate(Eigen::Vector3d(3.25, 7.5, 11.0));
  CHECK(f(0) == doctest::Approx(3.25).epsilon(1e-9));
  CHECK(f(1) == doctest::Approx(7.5).epsilon(1e-9));
  CHECK(f(2) == doctest::Approx(11.0).epsilon(1e-9));
  CHECK(f(3) == doctest::Approx(cubic(3.25, 7.5, 11.0)).epsilon(1e-9));
}

TEST_CASE("adaptive refinement keeps the partition of unity and lowers the error") {
  const spline::GridSamples s = blob_samples(24);
  spline::AdaptiveDensityOptions options;
  options.max_rms_rel = 1e-4;
  options.max_levels = 3;
  options.initial_cells = 2;
  options.max_control_points = 50000;
  options.min_gain_rate = 0.0;
  const spline::AdaptiveDensityResult r = spline::fit_density_adaptive(s, options);
  REQUIRE(r.levels.size() == 4);
  CHECK(r.stop_reason == spline::FitStopReason::MaxLevels);
  for (std::size_t l = 1; l < r.levels.size(); ++l) {
    CHECK(r.levels[l].control_points > r.levels[l - 1].control_points);
    CHECK(r.levels[l].rms_rel < r.levels[l - 1].rms_rel);
  }
  // Σ w_i B_i ≡ 1 (Eq. 4.3) on a lattice, including the domain faces.
  double worst = 0.0;
  for (int k = 0; k <= 8; ++k)
    for (int j = 0; j <= 8; ++j)
      for (int i = 0; i <= 8; ++i)
        worst = std::max(worst, std::abs(r.spline.weight_sum(Eigen::Vector3d(23.0 * i / 8, 23.0 * j / 8, 23.0 * k / 8)) - 1.0));
  CHECK(worst < 1e-12);
  // The reconstruction is the spline's density.
  CHECK(r.reconstruction[5 + 24 * (7 + 24 * 9)] ==
        doctest::Approx(r.spline.evaluate(Eigen::Vector3d(5, 7, 9))(3)).epsilon(1e-9));
}

TEST_CASE("adaptive fit respects the control point budget and beats the uniform fit at equal size") {
  const spline::GridSamples s = blob_samples(24);
  spline::AdaptiveDensityOptions options;
  options.max_rms_rel = 1e-6;
  options.max_control_points = 900;
  options.initial_cells = 2;
  options.min_gain_rate = 0.0;
  const spline::AdaptiveDensityResult r = spline::fit_density_adaptive(s, options);
  CHECK(r.spline.num_functions() <= 900);
  CHECK(r.stop_reason != spline::FitStopReason::Target);
  // The uniform B-spline with at least as many control points (9³ = 729 ≤ 900 < 10³) is worse
  // on a localized blob only if the adaptive fit used its budget where the error is.
  const spline::UniformBsplineFit uniform = spline::fit_uniform_bspline(s, {9, 9, 9});
  CHECK(r.error.rms_rel < uniform.error.rms_rel);
}

TEST_CASE("scattered fit on identity parameters agrees with the grid fit") {
  const int n = 9;
  const spline::GridSamples s = cubic_samples({n, n, n});
  Eigen::MatrixX3d uvw(n * n * n, 3);
  Eigen::MatrixXd targets(n * n * n, 4);
  for (int z = 0, v = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x, ++v) {
        uvw.row(v) << x / (n - 1.0), y / (n - 1.0), z / (n - 1.0);
        targets.row(v) << x, y, z, s.values[v];
      }
  spline::AdaptiveDensityOptions options;
  options.max_rms_rel = 1e-14;
  options.max_levels = 1;
  options.initial_cells = 2;
  options.fit.tolerance = 1e-13;
  options.fit.regularization = 1e-14;
  const spline::ScatteredDensityResult r = spline::fit_scattered_adaptive(uvw, targets, s.dims, options);
  CHECK(r.spline.dimension() == 4);
  const Eigen::VectorXd f = r.spline.evaluate(Eigen::Vector3d(0.3, 0.6, 0.9));
  CHECK(f(0) == doctest::Approx(0.3 * (n - 1)).epsilon(1e-8));
  CHECK(f(3) == doctest::Approx(cubic(0.3 * (n - 1), 0.6 * (n - 1), 0.9 * (n - 1))).epsilon(1e-8));
  Eigen::MatrixX3d outside = uvw;
  outside(3, 1) = 1.5;
  CHECK_THROWS_WITH_AS(spline::fit_scattered_adaptive(outside, targets, s.dims, options),
                       doctest::Contains("sample 3"), Error);
}

TEST_CASE("automatic budget: one control point per 16 samples within [64, 50000]") {
  CHECK(spline::automatic_control_point_budget(64 * 64 * 64) == 16384);
  CHECK(spline::automatic_control_point_budget(100) == 64);
  CHECK(spline::automatic_control_point_budget(103u * 94u * 161u) == 50000);
}

TEST_CASE("diminishing returns: the log-log slope of the last level against min_gain_rate") {
  spline::AdaptiveDensityOptions options;  // min_gain_rate 0.25, min_decrease_rel 0.02
  // Doubling the control points halves the RMS: slope 1.
  CHECK_FALSE(spline::level_gain_too_small({{1000, 0.1}, {2000, 0.05}}, options));
  // 8x the control points for a 10 % lower RMS: slope ln(1/0.9)/ln(8) = 0.0507.
  CHECK(spline::level_gain_too_small({{1000, 0.1}, {8000, 0.09}}, options));
  // Less than 2 % lower: stalled whatever the slope.
  CHECK(spline::level_gain_too_small({{1000, 0.1}, {1001, 0.099}}, options));
  options.min_gain_rate = 0.0;
  CHECK_FALSE(spline::level_gain_too_small({{1000, 0.1}, {8000, 0.09}}, options));
  CHECK_FALSE(spline::level_gain_too_small({{1000, 0.1}}, options));
}

TEST_CASE("adaptive fit names its stop reason") {
  const spline::GridSamples s = blob_samples(16);
  spline::AdaptiveDensityOptions options;
  options.initial_cells = 2;
  options.max_rms_rel = 0.5;  // the level-0 fit already reaches it
  CHECK(spline::fit_density_adaptive(s, options).stop_reason == spline::FitStopReason::Target);
  options.max_rms_rel = 1e-6;
  options.max_control_points = 130;  // level 0 has 125: no room for a level
  const spline::AdaptiveDensityResult budget = spline::fit_density_adaptive(s, options);
  CHECK(budget.stop_reason == spline::FitStopReason::Budget);
  CHECK(budget.levels.size() == 1);
  options.max_control_points = 0;  // automatic: 4096 / 16 = 256
  const spline::AdaptiveDensityResult automatic = spline::fit_density_adaptive(s, options);
  CHECK(automatic.spline.num_functions() <= 256);
  options.max_control_points = 50000;
  options.min_gain_rate = 100.0;  // no level can be that good
  const spline::AdaptiveDensityResult diminishing = spline::fit_density_adaptive(s, options);
  CHECK(diminishing.stop_reason == spline::FitStopReason::Diminishing);
  CHECK(diminishing.levels.size() == 2);
  CHECK(std::string(spline::fit_stop_reason_name(diminishing.stop_reason)) == "diminishing");
}

TEST_CASE("adaptive fit rejects bad options") {
  const spline::GridSamples s = cubic_samples({6, 6, 6});
  spline::AdaptiveDensityOptions options;
  options.max_rms_rel = 0.0;
  CHECK_THROWS_WITH_AS(spline::fit_density_adaptive(s, options), doctest::Contains("max_rms_rel"), Error);
  options = {};
  options.max_control_points = 10;
  CHECK_THROWS_WITH_AS(spline::fit_density_adaptive(s, options), doctest::Contains("max_control_points"), Error);
  options = {};
  options.min_gain_rate = -1.0;
  CHECK_THROWS_WITH_AS(spline::fit_density_adaptive(s, options), doctest::Contains("min_gain_rate"), Error);
  const spline::GridSamples flat = cubic_samples({6, 1, 6});
  CHECK_THROWS_WITH_AS(spline::fit_density_adaptive(flat, {}), doctest::Contains("along y"), Error);
}
