// SPDX-License-Identifier: MIT
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "core/spline/tspline.h"

namespace volspline::test {

// A T-spline with no tensor structure: random knot vectors drawn from a small set of values
// (with repeats), random positive weights. Not semi-standard, and parts of the box may be
// uncovered.
inline spline::TSpline random_tspline(int n, int dimension, unsigned seed, spline::TSplineAcceleration acceleration) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, 6);
  std::uniform_real_distribution<double> weight(0.5, 2.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double values[7] = {0.0, 0.1, 0.3, 0.35, 0.6, 0.8, 1.0};
  std::vector<spline::BlendingKnots> knots(n);
  Eigen::VectorXd weights(n);
  Eigen::MatrixXd points(n, dimension);
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      spline::LocalKnots r;
      do {
        for (double& k : r) k = values[pick(rng)];
        std::sort(r.begin(), r.end());
      } while (r[0] == r[4]);
      knots[i][a] = r;
    }
    weights[i] = weight(rng);
    for (int d = 0; d < dimension; ++d) points(i, d) = normal(rng);
  }
  return spline::TSpline(knots, weights, points, acceleration);
}

}  // namespace volspline::test
