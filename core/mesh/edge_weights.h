// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/mesh/halfedge_mesh.h"

namespace volspline::mesh {

/// Cotangent weight of every edge, length num_edges(): w_e = (cot α + cot β) / 2 with α, β the
/// angles opposite e in its two faces; a boundary edge gets the one-sided cot α / 2.
/// Sign convention: positive when the opposite angles are acute, negative possible for
/// obtuse (non-Delaunay) pairs; used as L_ij = +w_ij, L_ii = -Σ_j w_ij (negative semidefinite,
/// as libigl's cotmatrix). A face of zero area contributes 0 (its angles are undefined).
/// Scale invariant: uniform scaling of the positions does not change the weights.
std::vector<double> cotan_weights(const HalfedgeMesh& mesh);

/// Floater's mean-value weight of every halfedge h from vertex i to j, length num_halfedges():
/// w_h = (tan(α/2) + tan(β/2)) / |x_j - x_i|, with α, β the angles at x_i between edge ij and
/// the other edge at i of each face adjacent to ij (one term at a boundary edge). Not
/// symmetric (w_ij != w_ji in general); always ≥ 0, > 0 for non-degenerate faces, units 1/length.
/// A zero-length edge or a face with an angle of π at x_i contributes 0.
std::vector<double> mean_value_weights(const HalfedgeMesh& mesh);

/// Copies each edge weight to both of its halfedges, length num_halfedges().
/// Precondition: edge_weights.size() == num_edges().
std::vector<double> edge_to_halfedge_weights(const HalfedgeMesh& mesh,
                                             const std::vector<double>& edge_weights);

}  // namespace volspline::mesh
