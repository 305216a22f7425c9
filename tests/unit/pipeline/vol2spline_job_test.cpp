// SPDX-License-Identifier: MIT
#include "core/pipeline/vol2spline_job.h"

#include <cmath>
#include <limits>
#include <string>

#include <doctest/doctest.h>

#include "core/common/error.h"

using namespace volspline;

namespace {

// A bright ellipsoid on a dark background (two materials), n³ voxels.
volume::Volume ellipsoid(int n) {
  volume::Volume v;
  v.nx = v.ny = v.nz = n;
  v.spacing = Eigen::Vector3d(1.0, 1.0, 2.0);
  const double c = 0.5 * (n - 1);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double r = std::sqrt((x - c) * (x - c) / 25.0 + (y - c) * (y - c) / 16.0 + (z - c) * (z - c) / 12.0);
        v.samples.push_back(static_cast<float>(200.0 / (1.0 + std::exp(8.0 * (r - 1.0)))));
      }
  return v;
}

}  // namespace

TEST_CASE("vol2spline identity: density spline with identity geometry and stats") {
  const volume::Volume v = ellipsoid(16);
  pipeline::Vol2SplineOptions options;
  options.max_rms_rel = 0.02;
  options.initial_cells = 2;
  options.max_control_points = 2000;
  const pipeline::Vol2SplineResult r = pipeline::run_vol2spline(v, "ellipsoid", options);
  CHECK(r.spline.dimension() == 4);
  CHECK(r.stats.stop_reason == "target");
  CHECK(r.stats.max_control_points == 2000);
  CHECK(r.stats.voxels == 16u * 16u * 16u);
  CHECK(r.stats.density_rms_rel <= 0.02);
  CHECK(r.stats.density_rms_rel < r.stats.curve.front().rms_rel);
  CHECK(r.stats.control_points == r.spline.num_functions());
  CHECK(r.stats.curve.size() == static_cast<std::size_t>(r.stats.levels + 1));
  CHECK_FALSE(r.stats.frames_computed);
  CHECK(r.stats.min_scaled_jacobian == doctest::Approx(1.0).epsilon(1e-6));
  // X, Y, Z in physical units: voxel (4, 5, 6) with spacing (1, 1, 2).
  const Eigen::VectorXd f = r.spline.evaluate(Eigen::Vector3d(4, 5, 6));
  CHECK(f(2) == doctest::Approx(12.0).epsilon(1e-8));
  CHECK(f(3) == doctest::Approx(r.reconstruction[v.index(4, 5, 6)]).epsilon(1e-9));
}

TEST_CASE("vol2spline aligned: frame stages run and the fit covers [0, 1]^3") {
  const volume::Volume v = ellipsoid(14);
  pipeline::Vol2SplineOptions options;
  options.param = pipeline::Vol2SplineParam::Aligned;
  options.max_rms_rel = 0.02;
  options.initial_cells = 2;
  options.max_levels = 2;
  options.clusters = 2;
  const pipeline::Vol2SplineResult r = pipeline::run_vol2spline(v, "ellipsoid", options);
  CHECK(r.stats.frames_computed);
  CHECK(r.stats.frame_smoothness_final <= r.stats.frame_smoothness_initial);
  CHECK(r.uvw.rows() == 14 * 14 * 14);
  CHECK(r.spline.domain_min().norm() == 0.0);
  CHECK(r.spline.domain_max() == Eigen::Vector3d::Ones());
  CHECK(r.stats.density_rms_rel < 0.1);
  CHECK(r.frames.frames.size() == v.num_voxels());
}

TEST_CASE("vol2spline default budget is one control point per 16 voxels") {
  const volume::Volume v = ellipsoid(16);
  pipeline::Vol2SplineOptions options;
  options.max_rms_rel = 1e-6;  // out of reach: the budget or diminishing returns stop the fit
  options.initial_cells = 2;
  const pipeline::Vol2SplineResult r = pipeline::run_vol2spline(v, "ellipsoid", options);
  CHECK(r.stats.max_control_points == 16 * 16 * 16 / 16);
  CHECK(r.stats.control_points <= 256);
  CHECK((r.stats.stop_reason == "budget" || r.stats.stop_reason == "diminishing"));
}

TEST_CASE("vol2spline rejects bad options and tiny volumes") {
  const volume::Volume v = ellipsoid(8);
  pipeline::Vol2SplineOptions options;
  options.max_rms_rel = -1.0;
  CHECK_THROWS_WITH_AS(pipeline::run_vol2spline(v, "e", options), doctest::Contains("max_rms_rel"), Error);
  options = {};
  options.clusters = 1;
  CHECK_THROWS_WITH_AS(pipeline::run_vol2spline(v, "e", options), doctest::Contains("clusters"), Error);
  volume::Volume flat = v;
  flat.nz = 1;
  flat.samples.resize(64);
  CHECK_THROWS_WITH_AS(pipeline::run_vol2spline(flat, "flat.raw", {}), doctest::Contains("flat.raw"), Error);
  options = {};
  options.param = pipeline::Vol2SplineParam::Aligned;
  volume::Volume small = ellipsoid(4);
  CHECK_THROWS_WITH_AS(pipeline::run_vol2spline(small, "small.raw", options), doctest::Contains("at least 5"), Error);
}

TEST_CASE("vol2spline keeps the volume's origin and mirrored direction in X, Y, Z; the measures ignore them") {
  volume::Volume v = ellipsoid(12);
  pipeline::Vol2SplineOptions options;
  options.max_rms_rel = 0.05;
  options.initial_cells = 2;
  const pipeline::Vol2SplineResult plain = pipeline::run_vol2spline(v, "ellipsoid", options);
  v.origin = Eigen::Vector3d(5, -6, 7);
  v.direction = Eigen::Vector3d(-1, -1, 1).asDiagonal();  // an LPS-style frame: det = +1 here
  v.direction.col(0).swap(v.direction.col(1));            // and a swap of two axes: det = −1
  const pipeline::Vol2SplineResult world = pipeline::run_vol2spline(v, "ellipsoid", options);
  for (const Eigen::Vector3i& voxel : {Eigen::Vector3i(0, 0, 0), Eigen::Vector3i(3, 7, 10), Eigen::Vector3i(11, 11, 11)}) {
    const Eigen::VectorXd f = world.spline.evaluate(voxel.cast<double>());
    const Eigen::Vector3d expected = v.voxel_position(voxel.x(), voxel.y(), voxel.z());
    CHECK((f.head<3>() - expected).norm() < 1e-8);
    CHECK(f(3) == doctest::Approx(plain.spline.evaluate(voxel.cast<double>())(3)).epsilon(1e-12));
  }
  CHECK(world.stats.min_scaled_jacobian == doctest::Approx(plain.stats.min_scaled_jacobian));
  CHECK(world.stats.density_rms_rel == plain.stats.density_rms_rel);
}

TEST_CASE("vol2spline does not depend on the volume's units or where it sits") {
  // The same voxels with the spacing scaled by 1e-6, 1e6 and 1e9 and the origin moved by ±1e6:
  // the job runs on the unit-spacing copy, so the counts are equal and the relative measures
  // agree to 1e-9, for the plain fit and for the frame stages (whose Hessian feature scales with
  // 1 / spacing² and falls below the classification's round-off threshold at spacing 1e9).
  for (const pipeline::Vol2SplineParam param : {pipeline::Vol2SplineParam::Identity, pipeline::Vol2SplineParam::Aligned}) {
    const bool aligned = param == pipeline::Vol2SplineParam::Aligned;
    CAPTURE(aligned);
    const volume::Volume base = ellipsoid(12);
    pipeline::Vol2SplineOptions options;
    options.param = param;
    options.max_rms_rel = 0.002;
    options.max_control_points = 2000;
    options.initial_cells = 2;
    options.max_levels = 2;
    const pipeline::Vol2SplineResult reference = pipeline::run_vol2spline(base, "ellipsoid", options);
    REQUIRE(reference.stats.levels >= 1);  // the refinement's marking is part of what must not move
    struct Variant {
      double scale;
      double shift;
    };
    for (const Variant variant : {Variant{1e-6, 0.0}, Variant{1e6, 0.0}, Variant{1e9, 0.0}, Variant{1.0, 1e6}, Variant{1e6, -1e6}}) {
      CAPTURE(variant.scale);
      CAPTURE(variant.shift);
      volume::Volume moved = base;
      moved.spacing *= variant.scale;
      moved.origin.setConstant(variant.shift);
      const pipeline::Vol2SplineResult r = pipeline::run_vol2spline(moved, "moved ellipsoid", options);
      CHECK(r.stats.control_points == reference.stats.control_points);
      CHECK(r.stats.levels == reference.stats.levels);
      CHECK(r.stats.clusters == reference.stats.clusters);
      CHECK(r.stats.constraints == reference.stats.constraints);
      CHECK(r.stats.density_rms_rel == doctest::Approx(reference.stats.density_rms_rel).epsilon(1e-9));
      CHECK(r.stats.density_max_rel == doctest::Approx(reference.stats.density_max_rel).epsilon(1e-9));
      CHECK(r.stats.frame_smoothness_final == doctest::Approx(reference.stats.frame_smoothness_final).epsilon(1e-9));
      CHECK(r.stats.min_scaled_jacobian == doctest::Approx(reference.stats.min_scaled_jacobian).epsilon(1e-9));
      // X, Y, Z in the volume's own units and place; the density unchanged.
      const Eigen::Vector3d uvw = 0.37 * reference.spline.domain_max() + 0.63 * reference.spline.domain_min();
      const Eigen::VectorXd f = r.spline.evaluate(uvw), g = reference.spline.evaluate(uvw);
      const Eigen::Vector3d expected = g.head<3>() * variant.scale + Eigen::Vector3d::Constant(variant.shift);
      CHECK((f.head<3>() - expected).cwiseAbs().maxCoeff() <= 1e-9 * (variant.scale * 22.0 + std::abs(variant.shift)));
      CHECK(f(3) == doctest::Approx(g(3)).epsilon(1e-9));
    }
  }
}

TEST_CASE("vol2spline refuses a spacing it cannot normalize") {
  const auto message = [](const Eigen::Vector3d& spacing) {
    volume::Volume v = ellipsoid(6);
    v.spacing = spacing;
    try {
      pipeline::run_vol2spline(v, "bad.nrrd", {});
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(message(Eigen::Vector3d(1, 0, 1)).find("'bad.nrrd' has spacing (1, 0, 1); every voxel size must be a positive number") !=
        std::string::npos);
  CHECK(message(Eigen::Vector3d(1, std::numeric_limits<double>::infinity(), 1)).find("positive number") != std::string::npos);
  CHECK(message(Eigen::Vector3d(1e-300, 1, 1e300)).find("more than 1e12 apart") != std::string::npos);
  volume::Volume v = ellipsoid(6);
  v.origin.x() = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH_AS(pipeline::run_vol2spline(v, "bad.nrrd", {}), doctest::Contains("origin or direction that is not finite"), Error);
}
