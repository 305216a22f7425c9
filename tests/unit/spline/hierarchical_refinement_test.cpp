// SPDX-License-Identifier: MIT
#include "core/spline/hierarchical_refinement.h"

#include <random>

#include <doctest/doctest.h>

#include "core/spline/bspline_volume.h"

using namespace volspline;

namespace {

spline::TSpline uniform(int cells) {
  std::vector<double> grid(cells + 1);
  for (int i = 0; i <= cells; ++i) grid[i] = double(i) / cells;
  const std::vector<double> knots = spline::boundary_restricted_knots(grid);
  const int n = cells + 3;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd points(n * n * n, 3);
  for (int r = 0; r < points.rows(); ++r) points.row(r) << u(rng), u(rng), u(rng);
  return spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points));
}

}  // namespace

TEST_CASE("ray-traced knots on the initial grid are the uniform windows with boundary knots") {
  const spline::RefinementGrid grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {4, 4, 4});
  const spline::TSpline ts = uniform(4);
  for (int i = 0; i < ts.num_functions(); ++i)
    for (int a = 0; a < 3; ++a) {
      const auto r = grid.ray_knots(ts.knots()[i], a);
      // Functions anchored at the domain start share the anchor 0 with different R: compare
      // only where the anchor determines R (interior anchors).
      if (ts.knots()[i][a][1] < ts.knots()[i][a][2]) CHECK(r == ts.knots()[i][a]);
    }
  CHECK(grid.leaf_of(Eigen::Vector3d(1, 1, 1)) == 63);
  CHECK(grid.leaf_of(Eigen::Vector3d(0, 0, 0)) == 0);
}

TEST_CASE("refinement keeps the spline and the partition of unity") {
  spline::RefinementGrid grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {3, 3, 3});
  const spline::TSpline before = uniform(3);
  spline::TSpline ts = grid.split(before, {0, 13});
  std::vector<int> deeper;
  for (int leaf : grid.leaves())
    if (grid.cell_level(leaf) == 1 && grid.cell_min(leaf).norm() < 0.2) deeper.push_back(leaf);
  REQUIRE_FALSE(deeper.empty());
  ts = grid.split(ts, deeper);
  CHECK(grid.max_level() == 2);
  CHECK(grid.num_leaves() == 27 + 7 * 2 + 7 * static_cast<int>(deeper.size()));
  CHECK(ts.num_functions() > before.num_functions());
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst_sum = 0.0, worst_value = 0.0;
  for (int s = 0; s < 100000; ++s) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    worst_sum = std::max(worst_sum, std::abs(ts.weight_sum(p) - 1.0));
    if (s % 10 == 0) worst_value = std::max(worst_value, (ts.evaluate(p) - before.evaluate(p)).cwiseAbs().maxCoeff());
  }
  // Exact identities (Eq. 4.8/4.9) up to rounding.
  CHECK(worst_sum <= 1e-12);
  CHECK(worst_value <= 1e-12);
  // The leaf of a point inside a split cell is one of its children.
  const int leaf = grid.leaf_of(Eigen::Vector3d(0.01, 0.01, 0.01));
  CHECK(grid.cell_level(leaf) == 2);
  CHECK(grid.cell_max(leaf).maxCoeff() == doctest::Approx(1.0 / 12.0));
}
