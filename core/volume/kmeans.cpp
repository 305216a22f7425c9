// SPDX-License-Identifier: MIT
#include "core/volume/kmeans.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <random>

namespace volspline::volume {

namespace {

// Nearest centre of row i (ties: lower index) and the squared distance to it.
int nearest(const Eigen::MatrixXd& points, Eigen::Index i, const Eigen::MatrixXd& centers, double& distance) {
  int best = 0;
  distance = std::numeric_limits<double>::infinity();
  for (Eigen::Index c = 0; c < centers.rows(); ++c) {
    const double d = (points.row(i) - centers.row(c)).squaredNorm();
    if (d < distance) {
      distance = d;
      best = static_cast<int>(c);
    }
  }
  return best;
}

// A uniform double in [0, 1) from the 64-bit engine, independent of the standard library's
// distribution implementations (which may differ between platforms).
double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

}  // namespace

KMeansResult kmeans(const Eigen::MatrixXd& points, const KMeansOptions& options) {
  const Eigen::Index n = points.rows();
  const int k = options.clusters;
  assert(k >= 1 && n >= k && options.max_iterations >= 1);
  std::mt19937_64 rng(options.seed);
  KMeansResult result;
  result.centers.resize(k, points.cols());
  // k-means++: first centre uniform, then each next with probability proportional to D^2.
  Eigen::VectorXd d2(n);
  result.centers.row(0) = points.row(static_cast<Eigen::Index>(uniform(rng) * n));
  for (Eigen::Index i = 0; i < n; ++i) d2[i] = (points.row(i) - result.centers.row(0)).squaredNorm();
  for (int c = 1; c < k; ++c) {
    const double total = d2.sum();
    Eigen::Index pick = 0;
    if (total > 0) {
      const double target = uniform(rng) * total;
      double running = 0.0;
      pick = n - 1;
      for (Eigen::Index i = 0; i < n; ++i) {
        running += d2[i];
        if (running > target && d2[i] > 0) {
          pick = i;
          break;
        }
      }
    }
    result.centers.row(c) = points.row(pick);
    for (Eigen::Index i = 0; i < n; ++i) d2[i] = std::min(d2[i], (points.row(i) - result.centers.row(c)).squaredNorm());
  }

  result.assignment.assign(n, -1);
  Eigen::VectorXd distance(n);
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    bool changed = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      const int c = nearest(points, i, result.centers, distance[i]);
      if (c != result.assignment[i]) {
        result.assignment[i] = c;
        changed = true;
      }
    }
    result.iterations = iteration;
    if (!changed) {
      result.converged = true;
      break;
    }
    Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(k, points.cols());
    std::vector<Eigen::Index> counts(k, 0);
    for (Eigen::Index i = 0; i < n; ++i) {
      sums.row(result.assignment[i]) += points.row(i);
      ++counts[result.assignment[i]];
    }
    for (int c = 0; c < k; ++c) {
      if (counts[c] > 0) {
        result.centers.row(c) = sums.row(c) / static_cast<double>(counts[c]);
      } else {
        // Empty cluster: restart it at the point worst served by its centre (first on ties).
        Eigen::Index far = 0;
        for (Eigen::Index i = 1; i < n; ++i)
          if (distance[i] > distance[far]) far = i;
        result.centers.row(c) = points.row(far);
        distance[far] = 0.0;
      }
    }
  }
  result.within_sum_squares = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    result.assignment[i] = nearest(points, i, result.centers, distance[i]);
    result.within_sum_squares += distance[i];
  }
  return result;
}

}  // namespace volspline::volume
