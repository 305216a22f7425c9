// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

#include "core/spline/gpc_jacobian_lattice.h"
#include "core/spline/gpc_spline.h"
#include "tests/unit/spline/gpc_test_domains.h"

using volspline::polycube::GpcDomain;
using volspline::spline::GpcJacobianLattice;
using volspline::spline::GpcSpline;
using volspline::spline::sample_gpc_jacobian_lattice;
using namespace volspline::test;

TEST_CASE("gpc jacobian lattice: cell centres of every cuboid, F and its scaled Jacobian") {
  const std::vector<PlacedCuboid> boxes = two_cube_boxes();
  GpcSpline spline = placed_gpc_spline(boxes, {{3, 4, 3}, {4, 3, 4}});
  const GpcDomain& d = spline.domain();
  const int n = 3;
  const GpcJacobianLattice l = sample_gpc_jacobian_lattice(spline, n);
  REQUIRE(l.scaled_jacobian.size() == 2 * 27);
  REQUIRE(l.xyz.size() == 3 * 2 * 27);
  double worst = 0.0;
  for (int c = 0; c < 2; ++c)
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t s = static_cast<std::size_t>(27 * c + i + n * (j + n * k));
          const Eigen::Vector3d unit((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n);
          const Eigen::Vector3d x = boxes[c].placement.apply(unit.cwiseProduct(cuboid_size(d, c)));
          worst = std::max(worst, (x - Eigen::Vector3d(l.xyz[3 * s], l.xyz[3 * s + 1], l.xyz[3 * s + 2])).norm());
        }
  CHECK(worst <= 1e-6);  // float points
  CHECK(l.min_scaled_jacobian == doctest::Approx(1.0).epsilon(1e-6));
  CHECK(*std::max_element(l.scaled_jacobian.begin(), l.scaled_jacobian.end()) <= 1.0f + 1e-6f);

  place_at_anchors(spline, boxes, true);
  const GpcJacobianLattice m = sample_gpc_jacobian_lattice(spline, 2);
  CHECK(m.scaled_jacobian.size() == 2 * 8);
  CHECK(m.min_scaled_jacobian == doctest::Approx(-1.0).epsilon(1e-6));
  CHECK(*std::max_element(m.scaled_jacobian.begin(), m.scaled_jacobian.end()) <= -1.0f + 1e-6f);
}
