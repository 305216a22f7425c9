// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "core/spline/gpc_boundary_tessellation.h"
#include "core/spline/gpc_spline.h"
#include "tests/unit/spline/gpc_test_domains.h"

using volspline::polycube::GpcDomain;
using volspline::spline::GpcBoundaryTessellation;
using volspline::spline::GpcSpline;
using volspline::spline::GpcSplineOptions;
using volspline::spline::tessellate_gpc_boundary;
using namespace volspline::test;

namespace {

Eigen::Vector3d point(const std::vector<float>& xyz, std::uint32_t i) {
  return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
}

}  // namespace

TEST_CASE("gpc boundary tessellation: two glued cuboids give the union box, outward, tagged by cuboid") {
  const std::vector<PlacedCuboid> boxes = two_cube_boxes();
  const GpcSpline spline = placed_gpc_spline(boxes, {{3, 4, 3}, {4, 3, 4}});
  const GpcDomain& d = spline.domain();
  const int m = 5, lines = 3;
  const GpcBoundaryTessellation t = tessellate_gpc_boundary(spline, m, lines);

  // 5 Surface faces per cuboid; the glued face x = 1 is inside the solid.
  const std::size_t faces = 10;
  REQUIRE(t.surface_xyz.size() == faces * m * m * 3);
  CHECK(t.surface_uvw.size() == t.surface_xyz.size());
  CHECK(t.surface_cuboid.size() == faces * m * m);
  CHECK(t.surface_triangles.size() == faces * (m - 1) * (m - 1) * 6);
  const std::size_t segments = faces * 2 * lines * 4 * (m - 1);
  CHECK(t.line_xyz.size() == segments * 6);
  CHECK(t.line_uvw.size() == segments * 6);
  CHECK(t.line_cuboid.size() == segments);

  // Every point is its cuboid's placement of uvw ⊙ size (floats: 1e-6), on the union's boundary.
  const Eigen::Vector3d lo(0.0, 0.0, 0.0), hi(2.3, 0.8, 0.6);
  double worst = 0.0;
  int off_boundary = 0, wrong_side = 0;
  for (std::uint32_t i = 0; i < t.surface_cuboid.size(); ++i) {
    const int c = static_cast<int>(t.surface_cuboid[i]);
    const Eigen::Vector3d uvw = point(t.surface_uvw, i), x = point(t.surface_xyz, i);
    CHECK((uvw.array() >= 0.0).all());
    CHECK((uvw.array() <= 1.0).all());
    worst = std::max(worst, (x - boxes[c].placement.apply(uvw.cwiseProduct(cuboid_size(d, c)))).norm());
    const double gap = std::min((x - lo).cwiseAbs().minCoeff(), (x - hi).cwiseAbs().minCoeff());
    if (gap > 1e-6) ++off_boundary;
    if ((c == 0 && x(0) > 1.0 + 1e-6) || (c == 1 && x(0) < 1.0 - 1e-6)) ++wrong_side;
  }
  CHECK(worst <= 1e-6);
  CHECK(off_boundary == 0);
  CHECK(wrong_side == 0);

  // Triangles face out of the box, none lies on the glued face, and they cover the box's
  // surface: its area 2(2.3·0.8 + 2.3·0.6 + 0.8·0.6) (float points: 1e-5).
  double area = 0.0;
  int inward = 0, on_glued_face = 0;
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  for (std::size_t k = 0; k < t.surface_triangles.size(); k += 3) {
    const Eigen::Vector3d a = point(t.surface_xyz, t.surface_triangles[k]),
                          b = point(t.surface_xyz, t.surface_triangles[k + 1]),
                          c = point(t.surface_xyz, t.surface_triangles[k + 2]);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    area += 0.5 * n.norm();
    if (n.dot((a + b + c) / 3.0 - centre) <= 0.0) ++inward;
    if (std::abs(a(0) - 1.0) < 1e-6 && std::abs(b(0) - 1.0) < 1e-6 && std::abs(c(0) - 1.0) < 1e-6) ++on_glued_face;
  }
  CHECK(inward == 0);
  CHECK(on_glued_face == 0);
  CHECK(area == doctest::Approx(2.0 * (2.3 * 0.8 + 2.3 * 0.6 + 0.8 * 0.6)).epsilon(1e-5));

  // The iso-lines lie on the boundary too, with their cuboid's uvw.
  double line_worst = 0.0;
  for (std::uint32_t s = 0; s < t.line_cuboid.size(); ++s)
    for (std::uint32_t e = 0; e < 2; ++e) {
      const int c = static_cast<int>(t.line_cuboid[s]);
      const Eigen::Vector3d uvw = point(t.line_uvw, 2 * s + e), x = point(t.line_xyz, 2 * s + e);
      line_worst = std::max(line_worst, (x - boxes[c].placement.apply(uvw.cwiseProduct(cuboid_size(d, c)))).norm());
    }
  CHECK(line_worst <= 1e-6);
}

TEST_CASE("gpc boundary tessellation: a cuboid glued to itself shows its four other faces") {
  const GpcDomain d = torus_domain(false);
  GpcSplineOptions o;
  o.intervals = {{4, 2, 1}};
  const GpcSpline spline(d, o);
  const GpcBoundaryTessellation t = tessellate_gpc_boundary(spline, 3, 2);
  CHECK(t.surface_cuboid.size() == 4 * 9);
  CHECK(t.surface_triangles.size() == 4 * 4 * 6);
  // No face of constant u (faces 0 and 1): every point's u runs over the lattice.
  int u_faces = 0;
  for (std::size_t f = 0; f < 4; ++f) {
    bool constant_u = true;
    for (std::size_t i = 0; i < 9; ++i) constant_u = constant_u && t.surface_uvw[3 * (9 * f + i)] == t.surface_uvw[3 * 9 * f];
    u_faces += constant_u;
  }
  CHECK(u_faces == 0);
}
