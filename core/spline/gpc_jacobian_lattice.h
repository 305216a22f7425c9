// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/spline/gpc_spline.h"

namespace volspline::spline {

/// The scaled Jacobian of a geometric GPC spline (dimension 3) on a lattice of every cuboid.
struct GpcJacobianLattice {
  std::vector<float> scaled_jacobian;  ///< n³ values per cuboid (cuboids in order, i fastest), in [−1, 1]
  std::vector<float> xyz;              ///< F at the same points, 3 floats each, model units
  float min_scaled_jacobian = 1;       ///< smallest of scaled_jacobian
};

/// Samples every cuboid at the centres ((i + ½)/n, (j + ½)/n, (k + ½)/n) ⊙ size of an n×n×n
/// lattice of cells of its box: interior points, none on a face where a map onto a smooth
/// surface degenerates at the cuboid's edges. Values are mesh::scaled_jacobian of F's Jacobian
/// (≤ 0: folded). Preconditions (asserted): dimension 3, n ≥ 1.
GpcJacobianLattice sample_gpc_jacobian_lattice(const GpcSpline& spline, int n);

}  // namespace volspline::spline
