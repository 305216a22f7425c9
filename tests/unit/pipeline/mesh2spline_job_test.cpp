// SPDX-License-Identifier: MIT
#include "core/pipeline/mesh2spline_job.h"

#include <limits>

#include <doctest/doctest.h>

#include "core/common/error.h"
#include "../param/test_meshes.h"

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
  options.untangle = false;  // one coarse cell folds a lot; the untangling has its own tests
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
                       doctest::Contains("--max-rms"), Error);
}
