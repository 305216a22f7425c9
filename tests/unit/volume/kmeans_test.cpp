// SPDX-License-Identifier: MIT
#include "core/volume/kmeans.h"

#include <doctest/doctest.h>

using namespace volspline::volume;

TEST_CASE("kmeans: two separated groups are found exactly, with their means as centres") {
  // Rows 0..9 around (0, 0), rows 10..29 around (10, 5): known means and sum of squares.
  Eigen::MatrixXd points(30, 2);
  for (int i = 0; i < 30; ++i) {
    const double jitter = (i % 5) * 0.1 - 0.2;  // -0.2 .. 0.2, mean 0 over each group
    points.row(i) = i < 10 ? Eigen::RowVector2d(jitter, -jitter) : Eigen::RowVector2d(10 + jitter, 5 + jitter);
  }
  KMeansOptions options;
  options.clusters = 2;
  const KMeansResult result = kmeans(points, options);
  CHECK(result.converged);
  const int a = result.assignment[0];
  for (int i = 0; i < 30; ++i) CHECK(result.assignment[i] == (i < 10 ? a : 1 - a));
  CHECK((result.centers.row(a) - Eigen::RowVector2d(0, 0)).norm() < 1e-12);
  CHECK((result.centers.row(1 - a) - Eigen::RowVector2d(10, 5)).norm() < 1e-12);
  // Each jitter value appears twice per group of 10: sum of 2 * jitter^2 over both coordinates.
  const double per_five = 2 * (0.04 + 0.01 + 0 + 0.01 + 0.04);
  CHECK(result.within_sum_squares == doctest::Approx(6 * per_five).epsilon(1e-12));
  // Same seed, same bytes.
  const KMeansResult again = kmeans(points, options);
  CHECK(again.assignment == result.assignment);
  CHECK(again.centers == result.centers);
}

TEST_CASE("kmeans: one cluster is the mean, as many clusters as points is exact") {
  Eigen::MatrixXd points(4, 1);
  points << 1, 2, 4, 9;
  KMeansOptions options;
  options.clusters = 1;
  KMeansResult result = kmeans(points, options);
  CHECK(result.centers(0, 0) == doctest::Approx(4.0).epsilon(1e-14));
  CHECK(result.within_sum_squares == doctest::Approx(9 + 4 + 0 + 25).epsilon(1e-14));
  options.clusters = 4;
  result = kmeans(points, options);
  CHECK(result.within_sum_squares == 0.0);
}
