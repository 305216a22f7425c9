// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/mesh/halfedge_mesh.h"

namespace volspline::mesh {

/// Shortest paths along mesh edges from a set of source vertices.
struct GraphDistances {
  std::vector<double> distance;     ///< per vertex, model units; +infinity if unreachable
  std::vector<int> predecessor;     ///< per vertex, previous vertex on the path; no_id at a
                                    ///< source or an unreachable vertex
  std::vector<int> nearest_source;  ///< per vertex, index into `sources`; -1 if unreachable
};

/// Multi-source Dijkstra over the edge graph with Euclidean edge lengths (an upper bound of the
/// geodesic distance, used to seed and segment in later stages). O((V + E) log V).
/// Deterministic: vertices are settled in (distance, vertex id) order and a tie between two
/// equally short paths keeps the smaller predecessor id; a vertex listed several times in
/// `sources` belongs to its first occurrence. Preconditions (assert): every source id is a
/// vertex id.
GraphDistances graph_distances(const HalfedgeMesh& mesh, const std::vector<int>& sources);

/// Same with caller-given edge lengths (size num_edges(), each ≥ 0, e.g. anisotropic costs).
GraphDistances graph_distances(const HalfedgeMesh& mesh, const std::vector<int>& sources,
                               const std::vector<double>& edge_lengths);

/// Vertices of the shortest path from its source to `target` (source first, target last);
/// empty if `target` is unreachable.
std::vector<int> graph_path(const GraphDistances& distances, int target);

}  // namespace volspline::mesh
