// SPDX-License-Identifier: MIT
#include "core/pipeline/mesh2spline_job.h"

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/io/mesh_io.h"
#include "core/spline/jacobian_certificate.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

std::string error_of(const mesh::TriangleMesh& m) {
  try {
    pipeline::run_mesh2spline(m, "bad.off", {});
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("mesh2spline reproduces a cube") {
  pipeline::Mesh2SplineOptions options;
  options.initial_cells = 2;
  options.measure_samples = 12;
  const auto result = pipeline::run_mesh2spline(test::subdivided_cube(3), "cube", options);
  const auto& s = result.stats;
  CHECK(s.hausdorff_rel < 1e-3);
  CHECK(s.rms_rel < 1e-3);
  CHECK(s.negative_jacobian_fraction == 0.0);
  CHECK(s.min_scaled_jacobian > 0.99);  // the map is affine
  // The affine map's det J is one constant: every cell certified, the bound is the scaled Jacobian.
  CHECK(s.jacobian_certified_fraction == 1.0);
  CHECK(s.uncertified_cells.empty());
  CHECK(s.certificate_cells == result.spline.num_cells());
  CHECK(s.det_j_lower_bound_rel > 0.99);
  CHECK(s.semi_standard_max_error <= 1e-12);
  CHECK(s.flipped_triangles == 0);
  CHECK(s.grid_inverted_hexes == 0);
}

TEST_CASE("mesh2spline reproduces a sphere with both fits") {
  for (auto fit : {pipeline::Mesh2SplineFit::Grid, pipeline::Mesh2SplineFit::Meshless}) {
    pipeline::Mesh2SplineOptions options;
    options.fit = fit;
    options.max_rms_rel = 1e-3;
    options.max_levels = 2;
    options.measure_samples = 16;
    const auto result = pipeline::run_mesh2spline(test::cube_sphere(8), "sphere", options);
    const auto& s = result.stats;
    CAPTURE(static_cast<int>(fit));
    // Shape to 1e-3 of the bbox diagonal in the fitting rms; the two-sided surface distance
    // stays larger near the cuboid corners, where the cube-to-sphere map is singular.
    CHECK(s.rms_rel <= 1e-3);
    CHECK(s.hausdorff_rel < 5e-3);
    CHECK(s.negative_jacobian_fraction < 1e-3);  // see the report: corner regions may fold slightly
    CHECK(s.semi_standard_max_error <= 1e-12);
    CHECK(s.control_points == result.spline.num_functions());
    // The centre of the parameter domain maps near the centre of the ball.
    CHECK(result.spline.evaluate(Eigen::Vector3d(0.5, 0.5, 0.5)).norm() < 0.1);
  }
}

TEST_CASE("mesh2spline's untangler works toward the certificate: every cell of the shared sphere certified") {
  // Defaults: the passes and the polish leave 8 cells along the cuboid's edges and corners with
  // det J < 0 on the edge itself (there it depends on boundary control points only); the
  // certificate rounds move the boundary functions near them within the surface targets.
  const mesh::TriangleMesh sphere = io::read_mesh(std::string(VOLSPLINE_SHARED_DATA) + "/meshes/sphere.off");
  const auto result = pipeline::run_mesh2spline(sphere, "sphere", {});
  const auto& s = result.stats;
  CHECK(s.jacobian_certified_fraction == 1.0);
  CHECK(s.uncertified_cells.empty());
  CHECK(s.det_j_lower_bound_rel >= 0.0);
  CHECK(s.negative_jacobian_fraction == 0.0);
  CHECK(s.rms_rel <= 2e-3);
  CHECK(s.hausdorff_rel <= 1e-2);
  // The certificate agrees with an independent one of the written spline.
  CHECK(spline::certify_jacobian(result.spline).jacobian_certified_fraction == 1.0);
}

TEST_CASE("mesh2spline refuses a squeezed one-cuboid map when asked, for the GPC route") {
  // The shared sphere's map has least density 0.886 (no rescue round gains): squeezed below 0.9.
  const mesh::TriangleMesh sphere = io::read_mesh(std::string(VOLSPLINE_SHARED_DATA) + "/meshes/sphere.off");
  pipeline::Mesh2SplineOptions options;
  options.squeezed_below = 0.9;
  options.squeezed = pipeline::Mesh2SplineOptions::Squeezed::Refuse;
  bool refused = false;
  try {
    pipeline::run_mesh2spline(sphere, "sphere", options);
  } catch (const pipeline::SqueezedOneCuboid& e) {
    refused = true;
    CHECK(std::string(e.what()).find("mesh 'sphere'") != std::string::npos);
    CHECK(std::string(e.what()).find("squeezed") != std::string::npos);
    CHECK(e.squeeze_rounds == 0);
  }
  CHECK(refused);
  // Under the bound, or fitted all the same: one cuboid.
  options.squeezed_below = 0.85;
  options.max_levels = 0;
  CHECK(pipeline::run_mesh2spline(sphere, "sphere", options).stats.cuboids == 1);
  options.squeezed_below = 0.9;
  options.squeezed = pipeline::Mesh2SplineOptions::Squeezed::OneCuboid;
  CHECK(pipeline::run_mesh2spline(sphere, "sphere", options).stats.squeeze_rounds == 0);
}

TEST_CASE("mesh2spline accepts an inward-oriented mesh by flipping it") {
  auto m = test::subdivided_cube(2);
  m.triangles.col(1).swap(m.triangles.col(2));
  pipeline::Mesh2SplineOptions options;
  options.initial_cells = 1;
  options.measure_samples = 8;
  CHECK(pipeline::run_mesh2spline(m, "inward", options).stats.negative_jacobian_fraction == 0.0);
}

TEST_CASE("mesh2spline refines until the surface samples meet the surface target, not only the rms") {
  pipeline::Mesh2SplineOptions options;
  options.initial_cells = 1;
  options.max_levels = 1;
  options.measure_samples = 8;
  options.max_rms_rel = 0.5;  // met by any fit: only the surface target can ask for a level
  options.max_surface_error_rel = 0.5;
  options.untangle = pipeline::Mesh2SplineOptions::Untangle::Off;  // one coarse cell folds a lot; the untangling has its own tests
  const auto loose = pipeline::run_mesh2spline(test::cube_sphere(6), "sphere", options);
  CHECK(loose.stats.levels == 0);
  options.max_surface_error_rel = 1e-4;
  const auto tight = pipeline::run_mesh2spline(test::cube_sphere(6), "sphere", options);
  CHECK(tight.stats.levels == 1);
  CHECK(tight.stats.control_points > loose.stats.control_points);
  CHECK(tight.stats.hausdorff_rel < loose.stats.hausdorff_rel);
  CHECK(tight.stats.semi_standard_max_error <= 1e-12);
}

TEST_CASE("mesh2spline refuses bad input with a clear message") {
  auto open = test::subdivided_cube(2);
  open.triangles.conservativeResize(open.num_faces() - 1, 3);
  CHECK(error_of(open).find("not closed") != std::string::npos);
  CHECK(error_of(test::torus(12, 8)).find("genus 1") != std::string::npos);
  auto nan = test::subdivided_cube(2);
  nan.positions(3, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK(error_of(nan).find("bad.off") != std::string::npos);
  auto two = test::subdivided_cube(1);
  auto second = test::subdivided_cube(1);
  mesh::TriangleMesh both;
  both.positions.resize(16, 3);
  both.positions << two.positions, second.positions.array() + 5.0;
  both.triangles.resize(24, 3);
  both.triangles << two.triangles, second.triangles.array() + 8;
  CHECK(error_of(both).find("2 connected components") != std::string::npos);
  // Non-manifold: a third triangle on an existing edge.
  auto fin = test::subdivided_cube(1);
  fin.positions.conservativeResize(9, 3);
  fin.positions.row(8) << 3, 3, 3;
  fin.triangles.conservativeResize(13, 3);
  fin.triangles.row(12) << fin.triangles(0, 0), fin.triangles(0, 1), 8;
  CHECK(error_of(fin).find("bad.off") != std::string::npos);
  pipeline::Mesh2SplineOptions options;
  options.max_rms_rel = -1.0;
  CHECK_THROWS_WITH_AS(pipeline::run_mesh2spline(test::subdivided_cube(1), "c", options),
                       doctest::Contains("`max_rms_rel`"), Error);
}

TEST_CASE("mesh2spline does not depend on where the mesh sits or its units") {
  // The same mesh translated by ±1e6, scaled by 1e-6, 1e6 and 1e300: the job runs on the
  // unit-box copy, so the counts are equal and the relative measures agree to 1e-9. The base
  // coordinates lie on a 2^-30 grid, so the translated files hold the same mesh exactly (off the
  // grid, adding 1e6 rounds them by 1e-10 of the model's size: a different input, and the
  // refinement's marking may then differ by a few cells).
  pipeline::Mesh2SplineOptions options;
  options.max_levels = 1;
  options.measure_samples = 16;
  mesh::TriangleMesh base = test::cube_sphere(4);
  base.positions = (base.positions.array() * 0x1p30).round().matrix() * 0x1p-30;
  const auto reference = pipeline::run_mesh2spline(base, "sphere", options);
  REQUIRE(reference.stats.levels == 1);  // the refinement's marking is part of what must not move
  struct Variant {
    double scale;
    double shift;
  };
  for (const Variant v : {Variant{1.0, 1e6}, Variant{1e-6, 0.0}, Variant{1e6, 0.0}, Variant{1e300, 0.0},
                          Variant{1.0, -1e6}}) {
    CAPTURE(v.scale);
    CAPTURE(v.shift);
    mesh::TriangleMesh moved = base;
    moved.positions = (base.positions.array() * v.scale + v.shift).matrix();
    const auto result = pipeline::run_mesh2spline(moved, "moved sphere", options);
    CHECK(result.stats.control_points == reference.stats.control_points);
    CHECK(result.stats.levels == reference.stats.levels);
    CHECK(result.stats.rms_rel == doctest::Approx(reference.stats.rms_rel).epsilon(1e-9));
    CHECK(result.stats.hausdorff_rel == doctest::Approx(reference.stats.hausdorff_rel).epsilon(1e-9));
    CHECK(result.stats.negative_jacobian_fraction == reference.stats.negative_jacobian_fraction);
    // The spline is mapped back to the mesh's own coordinates.
    const Eigen::VectorXd centre = result.spline.evaluate(Eigen::Vector3d(0.5, 0.5, 0.5));
    const Eigen::VectorXd expected =
        (reference.spline.evaluate(Eigen::Vector3d(0.5, 0.5, 0.5)).array() * v.scale + v.shift).matrix();
    CHECK((centre - expected).cwiseAbs().maxCoeff() <= 1e-9 * v.scale);
  }
}

TEST_CASE("mesh2spline refuses coordinates it cannot normalize") {
  mesh::TriangleMesh wide = test::cube_sphere(4);
  wide.positions.col(0) *= 1.5e308;  // spans 3e308: beyond the doubles
  CHECK(error_of(wide).find("span more than the range of doubles") != std::string::npos);
  mesh::TriangleMesh far = test::cube_sphere(4);
  far.positions.array() += 1e14;  // a unit ball 1e14 from the origin keeps 2 digits of its shape
  CHECK(error_of(far).find("too few digits") != std::string::npos);
}

TEST_CASE("mesh2spline's untangling reports its passes and honours cancellation") {
  pipeline::Mesh2SplineOptions options;
  options.max_levels = 1;
  options.measure_samples = 8;
  std::vector<std::string> stages;
  const Progress stop_in_untangling([&stages](const std::string& stage, double) {
    stages.push_back(stage);
    return stage.rfind("untangle pass", 0) != 0;  // continue until the untangler's first pass
  });
  CHECK_THROWS_AS(pipeline::run_mesh2spline(test::cube_sphere(6), "sphere", options, stop_in_untangling), Cancelled);
  REQUIRE(!stages.empty());
  CHECK(stages.back() == "untangle pass 1");
}

TEST_CASE("mesh2spline reports fractions inside validation, layout and the surface map, and stops in each") {
  // Their shares of the job: validate [0, 0.05], cuboid layout [0.05, 0.1], surface map [0.1, 0.2].
  struct Share {
    std::string stage;
    double lo, hi;
    int min_inside;  // reports strictly inside the share: validation has 2 steps, the layout 39
  };                 // candidate frames after the first, the surface map 5 faces after the first
  const std::vector<Share> shares = {{"validate", 0.0, 0.05, 2}, {"cuboid layout", 0.05, 0.1, 20}, {"surface map", 0.1, 0.2, 5}};
  pipeline::Mesh2SplineOptions options;
  options.max_levels = 0;
  options.measure_samples = 8;
  std::vector<std::pair<std::string, double>> reports;
  const Progress record([&reports](const std::string& stage, double fraction) {
    reports.emplace_back(stage, fraction);
    return true;
  });
  pipeline::run_mesh2spline(test::cube_sphere(6), "sphere", options, record);
  double previous = 0.0;
  for (const auto& report : reports) {
    if (report.first == "volumetric map") break;
    CAPTURE(report.first);
    CHECK(report.second >= previous);  // the bar never runs backwards through these stages
    previous = report.second;
  }
  for (const Share& share : shares) {
    CAPTURE(share.stage);
    int inside = 0;
    for (const auto& [stage, fraction] : reports) {
      if (stage != share.stage) continue;
      CHECK(fraction >= share.lo);
      CHECK(fraction <= share.hi);
      if (fraction > share.lo && fraction < share.hi) ++inside;
    }
    CHECK(inside >= share.min_inside);
    // Cancelled at the stage's second report, i.e. inside the stage, not at the next one.
    int seen = 0;
    std::string last;
    const Progress stop([&](const std::string& stage, double) {
      last = stage;
      return !(stage == share.stage && ++seen == 2);
    });
    CHECK_THROWS_AS(pipeline::run_mesh2spline(test::cube_sphere(6), "sphere", options, stop), Cancelled);
    CHECK(last == share.stage);
  }
}
