// SPDX-License-Identifier: MIT
#pragma once

#include <functional>
#include <vector>

#include "core/mesh/halfedge_mesh.h"

namespace volspline::polycube {

/// Edge id of the mesh edge between adjacent vertices a and b, -1 if none.
int edge_between(const mesh::HalfedgeMesh& mesh, int a, int b);

/// Dijkstra from source to target entering only unblocked vertices (the target always) through
/// halfedges accepted by edge_ok (null: all). `length` per edge. Ties: smaller distance, then
/// smaller vertex id. Empty if there is no such path.
std::vector<int> restricted_path(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length,
                                 int source, int target, const std::vector<char>& blocked,
                                 const std::function<bool(int)>& edge_ok);

/// The largest c ≤ 1 with c·|x_a − x_b| ≤ length[e] on every edge e = (a, b) (0 if some edge has
/// zero length but its ends differ): c times the straight-line distance never overestimates a
/// path's length, the bound guided_path needs.
double straight_line_bound(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length);

/// A shortest path as restricted_path finds (same rules for blocked vertices and edge_ok, same
/// length), searched by A* with the estimate bound·|x_v − x_target| (bound from
/// straight_line_bound for this `length`): it explores about the ellipse around the two ends
/// instead of the disc around the source. Among paths of equal length it may pick another one
/// than restricted_path. Empty if there is no such path.
std::vector<int> guided_path(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length, double bound,
                             int source, int target, const std::vector<char>& blocked,
                             const std::function<bool(int)>& edge_ok);

/// Dijkstra from source to the nearest vertex with is_target set (the source itself does not
/// count), entering only unblocked or target vertices through halfedges accepted by edge_ok
/// (null: all). Same order and ties as restricted_path. Empty if no target is reached.
std::vector<int> path_to_nearest(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length, int source,
                                 const std::vector<char>& is_target, const std::vector<char>& blocked,
                                 const std::function<bool(int)>& edge_ok);

/// Face components separated by the flagged edges (per edge); returns the component count.
int face_components(const mesh::HalfedgeMesh& mesh, const std::vector<char>& cut_edge,
                    std::vector<int>& component);

/// Flags the edges of a vertex path (consecutive vertices must be adjacent).
void mark_path_edges(const mesh::HalfedgeMesh& mesh, const std::vector<int>& path,
                     std::vector<char>& cut_edge);

}  // namespace volspline::polycube
