// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/lens/lens_mesh.h"
#include "tests/unit/common/test_lenses.h"

using namespace volspline::lens;

namespace {
double signed_area(const LensMesh& m, int t) {
  const Eigen::Vector3d a = m.xyz.row(m.triangles(t, 0)), b = m.xyz.row(m.triangles(t, 1)), c = m.xyz.row(m.triangles(t, 2));
  return 0.5 * ((b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x()));
}
}  // namespace

TEST_CASE("grid: counts, coverage of the image, positive orientation") {
  const LensMesh g = build_grid(200, 100, 21);
  CHECK(g.grid_cols == 21);
  CHECK(g.grid_rows == 11);
  CHECK(g.triangles.rows() == 2 * 20 * 10);
  double area = 0;
  for (int t = 0; t < g.triangles.rows(); ++t) {
    CHECK(signed_area(g, t) > 0);
    area += signed_area(g, t);
  }
  CHECK(area == doctest::Approx(200.0 * 100.0).epsilon(1e-12));
  CHECK(build_grid(100, 100, 4).grid_rows == 4);
}

TEST_CASE("profile: 1 on the axis, 0 on the boundary, monotone") {
  CHECK(lens_profile(0.0) == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(lens_profile(1.0) == doctest::Approx(0.0).epsilon(1e-12));
  for (double d = 0; d < 1.0; d += 0.05) CHECK(lens_profile(d + 0.05) < lens_profile(d));
}

TEST_CASE("lens mesh: heights inside the ROI only, subdivision keeps orientation and area") {
  const LensMesh m = volspline::test::circle_lens_mesh("circle:60,60,25", 120, 120, 2.0, 25);
  CHECK(m.xyz.rows() > 25 * 25);  // steep flanks were split
  double area = 0;
  for (int t = 0; t < m.triangles.rows(); ++t) {
    CHECK(signed_area(m, t) > 0);
    area += signed_area(m, t);
  }
  CHECK(area == doctest::Approx(120.0 * 120.0).epsilon(1e-9));
  for (int v = 0; v < m.xyz.rows(); ++v) {
    const double r = std::hypot(m.xyz(v, 0) - 60, m.xyz(v, 1) - 60);
    if (r >= 25) CHECK(m.xyz(v, 2) == 0.0);
    if (r > 25 * 1.75 + 1e-9) CHECK(m.pinned[v]);
  }
  // Centre vertex (60, 60) carries the full height h0·R.
  CHECK(m.xyz.col(2).maxCoeff() == doctest::Approx(50.0).epsilon(1e-9));
}
