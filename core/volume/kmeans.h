// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace volspline::volume {

/// Options of kmeans.
struct KMeansOptions {
  int clusters = 2;          ///< K >= 1
  int max_iterations = 100;  ///< Lloyd iterations, >= 1
  std::uint64_t seed = 1;    ///< seed of the k-means++ initialisation (the only randomness)
};

/// Result of kmeans.
struct KMeansResult {
  Eigen::MatrixXd centers;         ///< K x d cluster centres
  std::vector<int> assignment;     ///< per point, index of its nearest centre (ties: lower index)
  double within_sum_squares = 0.0;  ///< sum of squared distances to the assigned centres
  int iterations = 0;
  bool converged = false;  ///< no assignment changed in the last iteration
};

/// Lloyd's k-means on the rows of `points` (n x d) with k-means++ seeding from a seeded RNG, so
/// the result depends only on the input and the options. An emptied cluster is re-seeded at the
/// point farthest from its centre. Precondition: n >= options.clusters >= 1, options valid.
KMeansResult kmeans(const Eigen::MatrixXd& points, const KMeansOptions& options);

}  // namespace volspline::volume
