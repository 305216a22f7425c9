// SPDX-License-Identifier: MIT
#include "core/pipeline/mesh2spline_measures.h"

#include <cmath>

#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/spline/bspline_volume.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

// F(u, v, w) = (x, 2v − 1, 2w − 1 + bulge·x²) with x = 2u − 1 on 3×3×3 cubic cells: linear and
// quadratic functions are reproduced exactly by the Greville abscissae and the blossoms.
spline::TSpline bulged_cube(double bulge) {
  const std::vector<double> knots = spline::boundary_restricted_knots({0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0});
  const int n = static_cast<int>(knots.size()) - 4;
  Eigen::MatrixXd points(n * n * n, 3);
  auto greville = [&](int i) { return (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0; };
  auto blossom_square = [&](int i) {
    return (knots[i + 1] * knots[i + 2] + knots[i + 1] * knots[i + 3] + knots[i + 2] * knots[i + 3]) / 3.0;
  };
  const spline::BsplineVolume shape({knots, knots, knots}, Eigen::MatrixXd::Zero(n * n * n, 3));
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x2 = 4.0 * blossom_square(i) - 4.0 * greville(i) + 1.0;  // (2u − 1)²
        points.row(shape.control_index(i, j, k)) << 2.0 * greville(i) - 1.0, 2.0 * greville(j) - 1.0,
            2.0 * greville(k) - 1.0 + bulge * x2;
      }
  return spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points),
                                     spline::TSplineAcceleration::FunctionLists);
}

}  // namespace

TEST_CASE("surface projection distance to a plane face is the height above it") {
  const spline::TSpline ts = bulged_cube(0.0);
  // Face w = 1 is the plane z = 1; start far from the foot point.
  const Eigen::Vector3d x(0.4, -0.3, 1.25);
  CHECK(pipeline::surface_projection_distance(ts, {0.9, 0.1, 1.0}, x) == doctest::Approx(0.25).epsilon(1e-12));
  // Beyond the face's edge the projection is clamped to the edge.
  const Eigen::Vector3d outside(1.5, 0.0, 1.0);
  CHECK(pipeline::surface_projection_distance(ts, {0.5, 0.5, 1.0}, outside) == doctest::Approx(0.5).epsilon(1e-12));
}

TEST_CASE("surface projection distance to a curved face matches a dense 1D search") {
  const double bulge = 0.5;
  const spline::TSpline ts = bulged_cube(bulge);
  const Eigen::Vector3d x(0.4, 0.2, 1.6);
  // The face w = 1 is z = 1 + bulge·s², s ∈ [−1, 1], at y = 2v − 1: the nearest point has y = 0.2.
  auto distance2 = [&](double s) { return (s - x.x()) * (s - x.x()) + std::pow(1.0 + bulge * s * s - x.z(), 2); };
  double lo = -1.0, hi = 1.0;
  for (int i = 0; i < 200; ++i) {  // ternary search: distance2 is unimodal on [−1, 1] here
    const double a = lo + (hi - lo) / 3.0, b = hi - (hi - lo) / 3.0;
    (distance2(a) < distance2(b) ? hi : lo) = distance2(a) < distance2(b) ? b : a;
  }
  const double expected = std::sqrt(distance2(0.5 * (lo + hi)));
  const double got = pipeline::surface_projection_distance(ts, {(x.x() + 1.0) / 2.0, (x.y() + 1.0) / 2.0, 1.0}, x);
  // Gauss–Newton from the vertical foot point, 6 steps at most: converged far below 1e-8.
  CHECK(got == doctest::Approx(expected).epsilon(1e-8));
  CHECK(got >= expected - 1e-12);
}

TEST_CASE("measures of a spline that is exactly the meshed cube") {
  const mesh::TriangleMesh cube = test::subdivided_cube(4);
  const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(cube, "cube");
  mesh::Positions vertex_uvw = (cube.positions.array() + 1.0) / 2.0;
  spline::RefinementGrid grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {3, 3, 3});
  const spline::TSpline refined = grid.split(bulged_cube(0.0), {0, 13, 26});
  pipeline::Mesh2SplineMeasureOptions options;
  options.surface_samples = 9;
  options.semi_standard_samples = 2000;
  const pipeline::Mesh2SplineMeasureResult m = pipeline::measure_mesh2spline(refined, hm, vertex_uvw, grid, std::sqrt(12.0), options);
  CHECK(m.hausdorff_rel < 1e-14);
  CHECK(m.rms_geo_rel < 1e-14);
  CHECK(m.min_scaled_jacobian == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(m.negative_jacobian_fraction == 0.0);
  CHECK(m.semi_standard_max_error < 1e-13);

  // The bulged spline misses the flat top by up to bulge at the top face's side edges.
  const spline::TSpline bulged = bulged_cube(0.1);
  const pipeline::Mesh2SplineMeasureResult b = pipeline::measure_mesh2spline(bulged, hm, vertex_uvw,
      spline::RefinementGrid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {3, 3, 3}), 1.0, options);
  CHECK(b.hausdorff_rel == doctest::Approx(0.1).epsilon(1e-12));
  CHECK(b.rms_geo_rel > 0.0);
  CHECK(b.rms_geo_rel < 0.1);

  options.surface_samples = 4;
  CHECK_THROWS_WITH_AS(pipeline::measure_mesh2spline(bulged, hm, vertex_uvw, grid, 1.0, options),
                       "mesh2spline measures: surface samples must be in [8, 512]", Error);
}
