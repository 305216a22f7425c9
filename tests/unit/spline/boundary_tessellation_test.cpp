// SPDX-License-Identifier: MIT
#include "core/spline/boundary_tessellation.h"

#include <Eigen/Geometry>
#include <doctest/doctest.h>

#include "core/spline/bspline_volume.h"

using namespace volspline;

namespace {

// F(uvw) = 2·uvw on [0, 1]³: control points at twice the Greville abscissae.
spline::TSpline scaled_identity() {
  const std::vector<double> knots = spline::boundary_restricted_knots({0.0, 1.0});
  Eigen::MatrixXd points(64, 3);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) points.row(i + 4 * (j + 4 * k)) << 2 * i / 3.0, 2 * j / 3.0, 2 * k / 3.0;
  return spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points));
}

}  // namespace

TEST_CASE("boundary tessellation of a cube: points on the faces, outward triangles enclosing its volume") {
  const spline::TSpline ts = scaled_identity();
  const spline::BoundaryTessellation b = spline::tessellate_boundary(ts, 5, 3);
  REQUIRE(b.surface_xyz.size() == 6 * 25 * 3);
  CHECK(b.surface_triangles.size() == 6 * 16 * 2 * 3);
  CHECK(b.line_xyz.size() == 6 * 2 * 3 * 16 * 2 * 3);
  for (std::size_t i = 0; i < b.surface_xyz.size(); ++i)
    CHECK(b.surface_xyz[i] == doctest::Approx(2.0f * b.surface_uvw[i]).epsilon(1e-6));
  // Divergence theorem: Σ over triangles of (a · (b × c)) / 6 is the enclosed volume, 8.
  double volume = 0.0;
  auto p = [&](std::uint32_t v) {
    return Eigen::Vector3d(b.surface_xyz[3 * v], b.surface_xyz[3 * v + 1], b.surface_xyz[3 * v + 2]);
  };
  for (std::size_t t = 0; t < b.surface_triangles.size(); t += 3)
    volume += p(b.surface_triangles[t]).dot(p(b.surface_triangles[t + 1]).cross(p(b.surface_triangles[t + 2]))) / 6.0;
  CHECK(volume == doctest::Approx(8.0).epsilon(1e-6));
}

TEST_CASE("boundary tessellation of some faces only: the exposed ones, in face order") {
  const spline::TSpline ts = scaled_identity();
  const spline::BoundaryTessellation b = spline::tessellate_boundary(ts, 3, 2, polycube::CubeFaceSet().with(5).with(1));
  REQUIRE(b.surface_uvw.size() == 2 * 9 * 3);
  CHECK(b.surface_uvw[0] == 1.0f);           // face 1: u = 1
  CHECK(b.surface_uvw[9 * 3 + 2] == 1.0f);   // face 5: w = 1
}
