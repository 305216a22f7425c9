// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"
#include "core/common/progress.h"

namespace volspline::lens {

/// Parameters of the flattening (§6.4, Algorithm 5).
struct FlattenOptions {
  double alpha = 0.0;        ///< Eq. 6.8 blend in [0, 1]: 0 rigid metric, 1 conformal metric
  double tol_rel = 1e-3;     ///< stop when |E^t − E^{t−1}| ≤ tol_rel·E^{t−1} (thesis: 0.1 %)
  int max_iterations = 300;  ///< local/global iterations at most
  double height_unit = 1.0;  ///< h in the weight (1 + h)·A·cotθ is z / height_unit (pixels per unit)
};

/// Result of the flattening.
struct FlattenResult {
  Eigen::MatrixX2d positions;  ///< n×2 flattened vertex positions, pixels
  int iterations = 0;
  bool converged = false;  ///< false if max_iterations was reached first
  double energy = 0;       ///< Eq. 6.2 at the last iteration
  double ms_setup = 0;     ///< standard triangles, weights, matrix assembly
  double ms_factorize = 0; ///< sparse LDLᵀ factorization (once)
  double ms_iterations = 0;///< all local/global iterations
};

/// Flattens a 3D lens mesh to the plane (§6.4, Algorithm 5). Every triangle gets its standard 2D
/// copy T^d (step 1); iterations alternate the local step (blended rigid/conformal metric per
/// triangle, Eq. 6.5–6.8) and the global step (Eq. 6.3 with weights (1+h)·A·cotθ, factorized once).
/// Pinned vertices stay at their row of `start` (n×2); free vertices start there too.
/// Preconditions: pinned.size() == xyz.rows(), at least one pinned vertex per connected component,
/// no degenerate triangle. Throws volspline::Error if the factorization fails.
FlattenResult flatten_lens(const mesh::Positions& xyz, const mesh::Triangles& triangles,
                           const std::vector<char>& pinned, const Eigen::MatrixX2d& start,
                           const FlattenOptions& options, const Progress& progress = {});

}  // namespace volspline::lens
