// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/triplet.h"

namespace volspline::mesh {

/// Which weights a graph Laplacian uses.
enum class LaplacianWeights {
  Uniform,    ///< w_ij = 1 (combinatorial / Tutte)
  Cotan,      ///< cotan_weights(), symmetric
  MeanValue,  ///< mean_value_weights(), not symmetric, always ≥ 0
};

/// Laplacian of a vertex function as triplets: row i holds L_ij = w_h for every outgoing
/// halfedge h = (i → j) and L_ii = -Σ_h w_h, so every row sums to zero (L kills constants) and
/// (L u)_i = Σ_j w_ij (u_j - u_i). With positive weights L is negative semidefinite.
/// Order (deterministic): rows by vertex id; in each row the diagonal first, then the
/// neighbours in one-ring order. An unreferenced vertex gets an empty (all-zero) row.
/// `halfedge_weights`: one weight per halfedge (size num_halfedges()), row i reads the weights
/// of i's outgoing halfedges; precondition checked by assert.
std::vector<Triplet> laplacian_triplets(const HalfedgeMesh& mesh,
                                        const std::vector<double>& halfedge_weights);

/// Same as above with the weights computed by the chosen scheme.
std::vector<Triplet> laplacian_triplets(const HalfedgeMesh& mesh, LaplacianWeights weights);

}  // namespace volspline::mesh
