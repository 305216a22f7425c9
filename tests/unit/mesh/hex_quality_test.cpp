// SPDX-License-Identifier: MIT
#include "core/mesh/hex_quality.h"

#include <cmath>

#include <doctest/doctest.h>

using namespace volspline;

TEST_CASE("hex scaled Jacobian: unit cube 1, mirrored −1") {
  std::array<Eigen::Vector3d, 8> x;
  for (int c = 0; c < 8; ++c) x[c] = Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1);
  CHECK(mesh::hex_min_scaled_jacobian(x) == doctest::Approx(1.0));
  for (auto& p : x) p.x() = -p.x();
  CHECK(mesh::hex_min_scaled_jacobian(x) == doctest::Approx(-1.0));
}

TEST_CASE("scaled Jacobian: scale-free, 1/√2 for a 45° shear, −1 for a zero column") {
  Eigen::Matrix3d j = 7.0 * Eigen::Matrix3d::Identity();
  CHECK(mesh::scaled_jacobian(j) == doctest::Approx(1.0).epsilon(1e-12));
  j.col(1) = Eigen::Vector3d(1.0, 1.0, 0.0);
  j.col(0) = Eigen::Vector3d(1.0, 0.0, 0.0);
  j.col(2) = Eigen::Vector3d(0.0, 0.0, 1.0);
  CHECK(mesh::scaled_jacobian(j) == doctest::Approx(1.0 / std::sqrt(2.0)).epsilon(1e-12));
  j.col(2).setZero();
  CHECK(mesh::scaled_jacobian(j) == -1.0);
}
