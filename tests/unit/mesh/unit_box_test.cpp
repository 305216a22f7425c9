// SPDX-License-Identifier: MIT
#include "core/mesh/unit_box.h"

#include <doctest/doctest.h>

#include "core/common/error.h"

using namespace volspline;

namespace {

mesh::TriangleMesh triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  mesh::TriangleMesh m;
  m.positions.resize(4, 3);
  m.positions.row(0) = a.transpose();
  m.positions.row(1) = b.transpose();
  m.positions.row(2) = c.transpose();
  m.positions.row(3) << 1e300, -1e300, 7;  // unused by any triangle: does not count
  m.triangles.resize(1, 3);
  m.triangles << 0, 1, 2;
  return m;
}

}  // namespace

TEST_CASE("unit_box_of centres the used vertices and scales the longest side to 1") {
  const auto m = triangle({10, 20, 30}, {13, 20, 30}, {10, 21, 32});
  const mesh::UnitBox box = mesh::unit_box_of(m, "t");
  CHECK(box.centre.isApprox(Eigen::Vector3d(11.5, 20.5, 31)));
  CHECK(box.side == 3.0);
  const mesh::TriangleMesh unit = box.to_unit(m);
  CHECK(unit.positions.topRows(3).cwiseAbs().maxCoeff() == 0.5);
  for (int v = 0; v < 3; ++v) {
    const Eigen::Vector3d p = m.positions.row(v).transpose();
    CHECK((box.from_unit(box.to_unit(p)) - p).norm() <= 1e-14 * p.norm());
  }
  Eigen::MatrixXd points(1, 4);
  points << 0.5, 0, 0, 42;
  const Eigen::MatrixXd back = box.from_unit_points(points);
  CHECK(back(0, 0) == 13.0);
  CHECK(back(0, 3) == 42.0);  // a density column is left as it is
}

TEST_CASE("unit_box_of gives the same unit copy, to rounding, for a scaled and moved model") {
  const auto m = triangle({0.1, 0.2, 0.3}, {1.7, 0.2, 0.3}, {0.1, 1.3, 0.9});
  const auto unit = mesh::unit_box_of(m, "m").to_unit(m);
  for (double scale : {1024.0, 1e-6, 1e6, 1e280}) {
    mesh::TriangleMesh big = m;
    big.positions.topRows(3) = (m.positions.topRows(3).array() * scale + 3 * scale).matrix();
    const auto unit_big = mesh::unit_box_of(big, "big").to_unit(big);
    CHECK((unit.positions.topRows(3) - unit_big.positions.topRows(3)).cwiseAbs().maxCoeff() <= 1e-14);
  }
}

TEST_CASE("unit_box_of handles 1e300-sized models and refuses what cannot be normalized") {
  const auto huge = triangle({-1e300, 0, 0}, {1e300, 0, 0}, {0, 1e300, 0});
  const mesh::UnitBox box = mesh::unit_box_of(huge, "huge");
  CHECK(box.to_unit(Eigen::Vector3d(1e300, 0, 0)).allFinite());
  CHECK_THROWS_WITH_AS(mesh::unit_box_of(triangle({-1.7e308, 0, 0}, {1.7e308, 0, 0}, {0, 1, 0}), "wide"),
                       doctest::Contains("span more than the range of doubles"), Error);
  CHECK_THROWS_WITH_AS(mesh::unit_box_of(triangle({1e20, 0, 0}, {1e20 + 1e4, 0, 0}, {1e20, 1, 0}), "far"),
                       doctest::Contains("too few digits"), Error);
  CHECK_THROWS_WITH_AS(mesh::unit_box_of(triangle({0, 0, 0}, {1, 0, 0}, {0, NAN, 0}), "nan"),
                       doctest::Contains("not finite"), Error);
}
