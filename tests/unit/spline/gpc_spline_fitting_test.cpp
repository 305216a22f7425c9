// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/io/gpc_json.h"
#include "core/spline/gpc_spline.h"
#include "core/spline/gpc_spline_fitting.h"
#include "tests/unit/spline/gpc_test_domains.h"

using volspline::Error;
using volspline::polycube::GpcDomain;
using volspline::spline::fit_gpc_spline;
using volspline::spline::gpc_uniform_intervals;
using volspline::spline::GpcFaceJoin;
using volspline::spline::GpcSamples;
using volspline::spline::GpcSpline;
using volspline::spline::GpcSplineFitOptions;
using volspline::spline::GpcSplineOptions;
using namespace volspline::test;

namespace {

using Map = std::function<Eigen::Vector3d(int cuboid, const Eigen::Vector3d& uvw)>;

// Per cuboid a lattice of 4·intervals + 1 nodes per axis (faces included): enough to make the
// least-squares problem unisolvent.
GpcSamples lattice_samples(const GpcSpline& spline, const Map& map, int per_interval = 4) {
  GpcSamples s;
  std::vector<Eigen::Vector3d> uvw, values;
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    const Eigen::Vector3d size = cuboid_size(spline.domain(), c);
    std::array<int, 3> n;
    for (int a = 0; a < 3; ++a) n[a] = per_interval * spline.intervals(c)[a] + 1;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          const Eigen::Vector3d h(size(0) * i / (n[0] - 1), size(1) * j / (n[1] - 1), size(2) * k / (n[2] - 1));
          s.cuboid.push_back(c);
          uvw.push_back(h);
          values.push_back(map(c, h));
        }
  }
  s.uvw.resize(static_cast<Eigen::Index>(uvw.size()), 3);
  s.values.resize(static_cast<Eigen::Index>(uvw.size()), 3);
  for (std::size_t r = 0; r < uvw.size(); ++r) {
    s.uvw.row(static_cast<Eigen::Index>(r)) = uvw[r].transpose();
    s.values.row(static_cast<Eigen::Index>(r)) = values[r].transpose();
  }
  return s;
}

// Largest ‖F − map‖ at random points of every cuboid (off the samples).
double max_error(const GpcSpline& spline, const Map& map, int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  for (int k = 0; k < count; ++k) {
    const int c = k % spline.num_cuboids();
    const Eigen::Vector3d size = cuboid_size(spline.domain(), c);
    const Eigen::Vector3d h(unit(rng) * size(0), unit(rng) * size(1), unit(rng) * size(2));
    worst = std::max(worst, (spline.evaluate(c, h) - map(c, h)).norm());
  }
  return worst;
}

// A cubic polynomial of total degree 3 in the global coordinates of placed boxes.
Map cubic_map(const std::vector<PlacedCuboid>& boxes) {
  return [boxes](int c, const Eigen::Vector3d& uvw) {
    const Eigen::Vector3d x = boxes[c].placement.apply(uvw);
    return Eigen::Vector3d(0.3 + x(0) - 0.5 * x(1) * x(1) + 0.25 * x(0) * x(1) * x(2) - 0.2 * x(2) * x(2) * x(2),
                           -0.1 * x(0) * x(0) * x(0) + x(1) + 0.4 * x(0) * x(2),
                           0.7 * x(2) + 0.3 * x(1) * x(1) * x(0) - 0.15 * x(0) * x(0) + 0.05 * x(1) * x(1) * x(1));
  };
}

GpcSplineFitOptions exact_options() {
  GpcSplineFitOptions o;
  o.regularization = 0.0;
  o.tolerance = 1e-14;
  return o;
}

void check_exact_cubic(const std::vector<PlacedCuboid>& boxes, GpcSplineOptions o, const char* what) {
  const GpcDomain d = glue_boxes(boxes);
  o.intervals = gpc_uniform_intervals(d, 0.45);
  GpcSpline spline(d, o);
  const Map map = cubic_map(boxes);
  const auto report = fit_gpc_spline(spline, lattice_samples(spline, map), exact_options());
  const double err = max_error(spline, map, 20000, 5);
  MESSAGE(what << ": " << spline.num_continued_interfaces() << "/" << d.interfaces.size()
               << " continued, " << spline.num_functions() << " functions, CG " << report.cg_iterations
               << " iterations, sample max error " << report.max_error << ", off-sample max error " << err);
  CHECK(report.converged);
  CHECK(report.unsampled_functions == 0);
  CHECK(report.max_error <= 1e-10);
  CHECK(err <= 1e-10);
}

}  // namespace

TEST_CASE("gpc fit: a cubic polynomial is recovered exactly over continued and clamped faces") {
  check_exact_cubic(two_cube_boxes(), {}, "two cuboids, continued");
  GpcSplineOptions clamped;
  clamped.clamped_interfaces = {0};
  check_exact_cubic(two_cube_boxes(), clamped, "two cuboids, clamped");
  check_exact_cubic(t_shape_boxes(), {}, "T with ill-points");
  check_exact_cubic(block_boxes({{{1.0, 0.7}, {0.8, 1.2}, {0.5, 0.9}}}, 11), {}, "2x2x2 rotated blocks");
}

TEST_CASE("gpc fit: a periodic map on a cuboid glued to itself converges at fourth order") {
  const GpcDomain d = torus_domain(false);
  // The solid torus around the z axis: u the angle (period 1), v the radius, w the height.
  const Map map = [](int, const Eigen::Vector3d& h) {
    const double r = 1.0 + h(1) - 0.15, angle = 2.0 * M_PI * h(0);
    return Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), h(2));
  };
  std::vector<double> errors;
  for (int nu : {4, 8, 16}) {
    GpcSplineOptions o;
    o.intervals = {{nu, 1, 1}};
    GpcSpline spline(d, o);
    const auto report = fit_gpc_spline(spline, lattice_samples(spline, map), exact_options());
    CHECK(report.converged);
    errors.push_back(max_error(spline, map, 20000, 6));
    // Periodic: the two ends of the tube agree in value and first derivative.
    const Eigen::Vector3d a(0.0, 0.1, 0.05), b(1.0, 0.1, 0.05);
    CHECK((spline.evaluate(0, a) - spline.evaluate(0, b)).norm() <= 1e-12);
    CHECK((spline.jacobian(0, a) - spline.jacobian(0, b)).norm() <= 1e-10);
  }
  MESSAGE("torus: max error at 4, 8, 16 intervals: " << errors[0] << ", " << errors[1] << ", " << errors[2]);
  CHECK(errors[0] / errors[1] >= 10.0);
  CHECK(errors[1] / errors[2] >= 10.0);
  CHECK(errors[2] <= 1e-4);
}

TEST_CASE("gpc fit: the eight's trilinear corner map is recovered exactly on its C0 GPC spline") {
  // The eight's faces all touch Type-1 ill-points, so every interface is clamped: the space holds
  // every map that is tricubic per cuboid and continuous, and the trilinear map of each cuboid's
  // corners is continuous because glued faces share their corners.
  const GpcDomain d = volspline::io::read_gpc_domain(VOLSPLINE_SOURCE_DIR "/tests/data/gpc/eight.gpc.json");
  GpcSplineOptions o;
  o.intervals = gpc_uniform_intervals(d, 0.1);
  GpcSpline spline(d, o);
  REQUIRE(spline.num_continued_interfaces() == 0);
  const Map map = [&d](int c, const Eigen::Vector3d& h) {
    const auto& cub = d.cuboids[c];
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (int k = 0; k < 8; ++k) {
      double weight = 1.0;
      for (int a = 0; a < 3; ++a) {
        const double s = h(a) / cub.size[a];
        weight *= (k >> a) & 1 ? s : 1.0 - s;
      }
      out += weight * cub.corner_xyz[k];
    }
    return out;
  };
  const auto report = fit_gpc_spline(spline, lattice_samples(spline, map, 2), exact_options());
  const double err = max_error(spline, map, 20000, 7);
  MESSAGE("eight: " << spline.num_functions() << " functions, " << report.samples << " samples, CG "
                    << report.cg_iterations << ", max error " << err);
  CHECK(report.converged);
  CHECK(err <= 1e-10);
}

TEST_CASE("gpc fit: unsampled functions keep their control points; bad samples throw") {
  const GpcDomain d = glue_boxes(two_cube_boxes());
  GpcSplineOptions o;
  o.intervals = {{3, 4, 3}, {4, 3, 4}};
  GpcSpline spline(d, o);
  Eigen::MatrixXd start = Eigen::MatrixXd::Constant(spline.num_functions(), 3, 0.5);
  spline.set_points(start);
  // Samples in cuboid 0 only: functions living in cuboid 1 alone are not reached.
  GpcSamples s;
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int m = 4000;
  s.uvw.resize(m, 3);
  s.values.resize(m, 3);
  for (int k = 0; k < m; ++k) {
    s.cuboid.push_back(0);
    s.uvw.row(k) << unit(rng), 0.8 * unit(rng), 0.6 * unit(rng);
    s.values.row(k) << 1.0, 2.0, 3.0;
  }
  GpcSplineFitOptions fit;
  fit.regularization = 1e-10;
  const auto report = fit_gpc_spline(spline, s, fit);
  CHECK(report.converged);
  CHECK(report.unsampled_functions > 0);
  CHECK(report.max_error <= 1e-6);
  int kept = 0;
  for (int i = 0; i < spline.num_functions(); ++i) kept += spline.points().row(i) == start.row(i);
  CHECK(kept == report.unsampled_functions);

  GpcSamples bad = s;
  bad.cuboid.pop_back();
  CHECK_THROWS_WITH_AS(fit_gpc_spline(spline, bad), doctest::Contains("expected m, m and m x 3"), Error);
  bad = s;
  bad.cuboid[5] = 2;
  CHECK_THROWS_WITH_AS(fit_gpc_spline(spline, bad), doctest::Contains("sample 5 names cuboid 2"), Error);
  bad = s;
  bad.uvw(3, 0) = 1.5;
  CHECK_THROWS_WITH_AS(fit_gpc_spline(spline, bad), doctest::Contains("outside cuboid 0"), Error);
  bad = s;
  bad.values(1, 1) = std::nan("");
  CHECK_THROWS_WITH_AS(fit_gpc_spline(spline, bad), doctest::Contains("not finite"), Error);
  GpcSplineFitOptions wrong;
  wrong.regularization = -1.0;
  CHECK_THROWS_WITH_AS(fit_gpc_spline(spline, s, wrong), doctest::Contains("regularization"), Error);
  wrong = {};
  wrong.max_iterations = 0;
  CHECK_THROWS_WITH_AS(fit_gpc_spline(spline, s, wrong), doctest::Contains("max_iterations"), Error);
}

TEST_CASE("gpc fit: sample weights give the weighted least-squares solution") {
  // Every sample twice, with values a and b and weights 1 and 3: the fit of a constant map is the
  // weighted mean (a + 3b)/4 everywhere; the reported errors are unweighted.
  const GpcDomain d = glue_boxes(two_cube_boxes());
  GpcSplineOptions o;
  o.intervals = {{2, 2, 2}, {2, 2, 2}};
  GpcSpline spline(d, o);
  const Eigen::Vector3d a(1.0, 2.0, 3.0), b(2.0, 2.0, -1.0);
  GpcSamples one = lattice_samples(spline, [&](int, const Eigen::Vector3d&) { return a; });
  const Eigen::Index m = one.uvw.rows();
  GpcSamples s;
  s.cuboid = one.cuboid;
  s.cuboid.insert(s.cuboid.end(), one.cuboid.begin(), one.cuboid.end());
  s.uvw.resize(2 * m, 3);
  s.uvw << one.uvw, one.uvw;
  s.values.resize(2 * m, 3);
  s.values << one.values, one.values.rowwise() + (b - a).transpose();
  s.weight.assign(static_cast<std::size_t>(m), 1.0);
  s.weight.resize(static_cast<std::size_t>(2 * m), 3.0);
  GpcSplineFitOptions fit;
  fit.regularization = 0.0;
  const auto report = fit_gpc_spline(spline, s, fit);
  CHECK(report.converged);
  const Eigen::Vector3d mean = (a + 3.0 * b) / 4.0;
  CHECK((spline.evaluate(1, Eigen::Vector3d(0.3, 0.2, 0.1)) - mean).norm() <= 1e-10);
  CHECK(report.max_error == doctest::Approx(0.75 * (b - a).norm()).epsilon(1e-9));
  GpcSamples bad = s;
  bad.weight[4] = 0.0;
  CHECK_THROWS_WITH_AS(fit_gpc_spline(spline, bad), doctest::Contains("weight"), Error);
  bad.weight.pop_back();
  CHECK_THROWS_WITH_AS(fit_gpc_spline(spline, bad), doctest::Contains("weights for"), Error);
}

TEST_CASE("gpc fit: knot lines refined where the misfit is lower it monotonically with fewer functions than uniform") {
  // The solid torus with a bump near u = 0.3: the misfit sits in a few intervals of u.
  const GpcDomain d = torus_domain(false);
  const Map map = [](int, const Eigen::Vector3d& h) {
    const double bump = 0.04 * std::exp(-std::pow((h(0) - 0.3) / 0.03, 2));
    const double r = 1.0 + h(1) - 0.15 + bump, angle = 2.0 * M_PI * h(0);
    return Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), h(2));
  };
  GpcSplineOptions dense;
  dense.intervals = {{64, 2, 2}};
  const GpcSamples samples = lattice_samples(GpcSpline(d, dense), map, 2);
  const std::vector<std::array<double, 3>> spacing = {{1.0 / 128, 0.3 / 4, 0.2 / 4}};  // the samples'
  const double target = 4e-5;
  GpcSplineOptions o;
  o.intervals = {{4, 1, 1}};
  GpcSpline spline(d, o);
  double rms = fit_gpc_spline(spline, samples, exact_options()).rms_error;
  for (int level = 1; level <= 10 && rms > target; ++level) {
    GpcSplineOptions refined;
    refined.knot_lines = volspline::spline::gpc_refined_knot_lines(spline, samples, 1.4, spacing);
    GpcSpline next(d, refined);
    CHECK(next.num_functions() > spline.num_functions());
    const double r = fit_gpc_spline(next, samples, exact_options()).rms_error;
    CHECK(r <= rms * (1.0 + 1e-9));  // nested spaces: least squares cannot get worse
    rms = r;
    spline = std::move(next);
  }
  REQUIRE(rms <= target);
  // Uniform knots need more: the fewest functions over n_u = 4 .. 64, n_v = n_w = 1, 2 at the same rms.
  int uniform = 0;
  for (int nu = 4; nu <= 64 && uniform == 0; nu *= 2)
    for (int nvw : {1, 2}) {
      GpcSplineOptions u;
      u.intervals = {{nu, nvw, nvw}};
      GpcSpline us(d, u);
      if (fit_gpc_spline(us, samples, exact_options()).rms_error <= target) {
        uniform = us.num_functions();
        break;
      }
    }
  MESSAGE("rms <= " << target << ": adaptive " << spline.num_functions() << " functions, uniform " << uniform);
  CHECK(uniform >= 2 * spline.num_functions());
}

TEST_CASE("gpc marking: the functions at a sample named first are split even where the squared misfit is elsewhere") {
  // A torus fitted to a map with a broad ripple (most of the squared misfit) and one sample far
  // off at u = 0.8 (a thin spike: little of the sum).
  const GpcDomain d = torus_domain(false);
  const Map map = [](int, const Eigen::Vector3d& h) {
    const double r = 1.0 + h(1) - 0.15 + 0.05 * std::sin(8.0 * M_PI * h(0)) * (h(0) < 0.5 ? 1.0 : 0.0);
    const double angle = 2.0 * M_PI * h(0);
    return Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), h(2));
  };
  GpcSplineOptions o;
  o.intervals = {{8, 1, 1}};
  GpcSpline spline(d, o);
  GpcSamples samples = lattice_samples(spline, map, 4);
  Eigen::Index spike = -1;
  for (Eigen::Index s = 0; s < samples.uvw.rows() && spike < 0; ++s)
    if (std::abs(samples.uvw(s, 0) - 0.8125) < 1e-12) spike = s;
  REQUIRE(spike >= 0);
  samples.values(spike, 2) += 0.02;
  fit_gpc_spline(spline, samples, exact_options());
  std::vector<int> ids;
  std::vector<double> values;
  spline.basis_at(samples.cuboid[spike], samples.uvw.row(spike).transpose(), {0, 0, 0}, ids, values);
  const double largest = *std::max_element(values.begin(), values.end());
  auto marks_spike = [&](const std::vector<int>& marked) {
    for (std::size_t k = 0; k < ids.size(); ++k)
      if (values[k] >= 0.5 * largest && !std::binary_search(marked.begin(), marked.end(), ids[k])) return false;
    return true;
  };
  const std::vector<int> plain = volspline::spline::gpc_marked_functions(spline, samples, 0.3, 1000, 2);
  const std::vector<int> first =
      volspline::spline::gpc_marked_functions(spline, samples, 0.3, 1000, 2, {static_cast<int>(spike)});
  CHECK_FALSE(marks_spike(plain));
  CHECK(marks_spike(first));
  CHECK(std::is_sorted(first.begin(), first.end()));
  // A function at the depth limit is never taken, named or not.
  CHECK(volspline::spline::gpc_marked_functions(spline, samples, 0.3, 1000, 0, {static_cast<int>(spike)}).empty());
  CHECK_THROWS_AS(volspline::spline::gpc_marked_functions(spline, samples, 0.3, 1000, 2, {-1}), Error);
}
