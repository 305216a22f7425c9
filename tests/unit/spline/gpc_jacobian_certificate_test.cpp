// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <vector>

#include "core/spline/gpc_jacobian_certificate.h"
#include "core/spline/gpc_spline.h"
#include "tests/unit/spline/gpc_test_domains.h"

using volspline::spline::certify_gpc_jacobian;
using volspline::spline::GpcSpline;
using namespace volspline::test;

TEST_CASE("certify_gpc_jacobian: a placed T certifies every cell of every cuboid box, its mirror image none") {
  // Five unit cubes, 3×3×3 cells each: F is each cuboid's rigid placement (scaled Jacobian 1).
  const std::vector<PlacedCuboid> boxes = t_shape_boxes();
  GpcSpline spline = placed_gpc_spline(boxes, std::vector<std::array<int, 3>>(5, {3, 3, 3}));
  const auto certificate = certify_gpc_jacobian(spline);
  CHECK(certificate.cells == 5 * 27);  // patch cells beyond a continued face are the neighbour's
  CHECK(certificate.certified_cells == 5 * 27);
  CHECK(certificate.jacobian_certified_fraction == 1.0);
  CHECK(certificate.det_j_lower_bound_rel == doctest::Approx(1.0).epsilon(1e-9));
  CHECK(certificate.uncertified.empty());
  CHECK(certificate.cell_bound_rel.size() == 5 * 27);

  place_at_anchors(spline, boxes, true);
  const auto mirrored = certify_gpc_jacobian(spline);
  CHECK(mirrored.certified_cells == 0);
  REQUIRE(mirrored.uncertified.size() == 5 * 27);
  CHECK(mirrored.uncertified.back().cuboid == 4);
  CHECK(mirrored.uncertified.back().bound.status == volspline::spline::JacobianCellStatus::Negative);
  CHECK(mirrored.det_j_lower_bound_rel == doctest::Approx(-1.0).epsilon(1e-9));
}
