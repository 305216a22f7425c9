// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cstring>
#include <random>
#include <vector>

#include "core/spline/node_jacobians.h"

using namespace volspline;

TEST_CASE("scattered_linear (AVX2 where the CPU has it) gives the bits of the plain sum of x_c g_c^T") {
  std::mt19937_64 rng(9);
  std::normal_distribution<double> entry(0.0, 1.0);
  const int columns = 40;
  Eigen::VectorXd x(3 * columns);
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = entry(rng);
  std::vector<double> x4;
  spline::detail::NodeJacobians::pad(x, x4);
  for (int round = 0; round < 500; ++round) {
    const int count = static_cast<int>(rng() % 70);
    std::vector<int> column(count);
    std::vector<Eigen::Vector3d> g(count);
    for (int e = 0; e < count; ++e) {
      column[e] = static_cast<int>(rng() % columns);
      g[e] = Eigen::Vector3d(entry(rng), entry(rng), entry(rng));
    }
    Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();
    for (int e = 0; e < count; ++e) expected += x.segment<3>(3 * column[e]) * g[e].transpose();
    const Eigen::Matrix3d m =
        spline::detail::scattered_linear(column.data(), count ? g.front().data() : nullptr, 0, count, x4.data());
    REQUIRE(std::memcmp(m.data(), expected.data(), sizeof(double) * 9) == 0);
  }
}
