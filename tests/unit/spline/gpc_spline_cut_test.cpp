// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/spline/gpc_spline.h"
#include "core/spline/gpc_spline_cut.h"
#include "tests/unit/spline/gpc_test_domains.h"

using volspline::polycube::GpcDomain;
using volspline::spline::gpc_spline_cut;
using volspline::spline::GpcSpline;
using volspline::spline::GpcSplineCut;
using volspline::spline::GpcSplineOptions;
using namespace volspline::test;

TEST_CASE("gpc spline cut: each cuboid's plane at its own parameter, scaled Jacobian of F") {
  const std::vector<PlacedCuboid> boxes = two_cube_boxes();
  GpcSpline spline = placed_gpc_spline(boxes, {{3, 4, 3}, {4, 3, 4}});
  const GpcDomain& d = spline.domain();
  const int m = 6;
  for (int axis = 0; axis < 3; ++axis)
    for (double t : {0.0, 0.3, 1.0}) {
      CAPTURE(axis);
      CAPTURE(t);
      const GpcSplineCut cut = gpc_spline_cut(spline, axis, t, m);
      REQUIRE(cut.xyz.size() == 2 * m * m * 3);
      CHECK(cut.cuboid.size() == 2 * m * m);
      REQUIRE(cut.uvw.size() == 2 * m * m * 3);
      CHECK(cut.scaled_jacobian.size() == 2 * m * m);
      CHECK(cut.triangles.size() == 2 * (m - 1) * (m - 1) * 6);
      CHECK(std::all_of(cut.triangles.begin(), cut.triangles.end(), [&](std::uint32_t i) { return i < 2 * m * m; }));
      // Point (i, j) of cuboid c is placement(uvw ⊙ size) with uvw on face 2·axis moved to t.
      double worst = 0.0;
      for (int c = 0; c < 2; ++c)
        for (int j = 0; j < m; ++j)
          for (int i = 0; i < m; ++i) {
            const std::size_t k = static_cast<std::size_t>(c * m * m + i + m * j);
            CHECK(cut.cuboid[k] == static_cast<std::uint32_t>(c));
            Eigen::Vector3d uvw = volspline::polycube::cube_face_point(2 * axis, double(i) / (m - 1), double(j) / (m - 1));
            uvw(axis) = t;
            const Eigen::Vector3d x = boxes[c].placement.apply(uvw.cwiseProduct(cuboid_size(d, c)));
            worst = std::max(worst, (x - Eigen::Vector3d(cut.xyz[3 * k], cut.xyz[3 * k + 1], cut.xyz[3 * k + 2])).norm());
            // Its local coordinates, for the browser's uncertified-cell test.
            worst = std::max(worst, (uvw.cwiseProduct(cuboid_size(d, c)) - Eigen::Vector3d(cut.uvw[3 * k], cut.uvw[3 * k + 1], cut.uvw[3 * k + 2])).norm());
          }
      CHECK(worst <= 1e-6);
      // A rotation everywhere: scaled Jacobian 1 (floats: 1e-6).
      CHECK(cut.min_scaled_jacobian == doctest::Approx(1.0).epsilon(1e-6));
      CHECK(*std::max_element(cut.scaled_jacobian.begin(), cut.scaled_jacobian.end()) <= 1.0f + 1e-6f);
    }

  // The mirror image folds every point: scaled Jacobian −1.
  place_at_anchors(spline, boxes, true);
  const GpcSplineCut folded = gpc_spline_cut(spline, 2, 0.5, 4);
  CHECK(folded.min_scaled_jacobian == doctest::Approx(-1.0).epsilon(1e-6));
  CHECK(*std::max_element(folded.scaled_jacobian.begin(), folded.scaled_jacobian.end()) <= -1.0f + 1e-6f);
}

TEST_CASE("gpc spline cut: all zero control points give a degenerate cut (scaled Jacobian −1)") {
  const GpcDomain d = torus_domain(true);
  GpcSplineOptions o;
  o.intervals = {{3, 2, 2}};
  const GpcSpline spline(d, o);
  const GpcSplineCut cut = gpc_spline_cut(spline, 0, 0.5, 3);
  REQUIRE(cut.xyz.size() == 9 * 3);
  CHECK(std::all_of(cut.xyz.begin(), cut.xyz.end(), [](float x) { return x == 0.0f; }));
  CHECK(cut.min_scaled_jacobian == -1.0f);
}
