// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include "core/common/progress.h"
#include "core/mesh/triangle_mesh.h"
#include "core/param/hex_grid_untangling.h"

namespace volspline::param {

/// Options of raise_min_scaled_jacobian.
struct MinQualityOptions {
  double target = 0.3;    ///< work on the hexes whose corner scaled Jacobian is below this, in (−1, 1]
  int max_sweeps = 60;    ///< Gauss–Seidel sweeps over the worked-on nodes, ≥ 1
  double first_step = 0.3;  ///< first trial step, fraction of the node's shortest hex edge, in (0, 1]
  int halvings = 7;       ///< the step is halved at most this often before a node is left, ≥ 0
  /// Per node, the longest hex edge a move may leave at it (the scaled Jacobian ignores aspect
  /// ratio, so a node may otherwise walk away stretching its hexes into long right-angled boxes);
  /// empty: 3 times the node's longest edge on entry. Callers that raise in several calls pass
  /// the bound of the first (longest_hex_edges) so that it holds across them.
  std::vector<double> max_edge;
  /// Per node, the shortest hex edge a move may leave at it (the scaled Jacobian ignores size too,
  /// so nodes may otherwise close up on a neighbour until round-off decides the sign of their
  /// hexes); empty: no bound.
  std::vector<double> min_edge;
  /// 0: the greedy ascent of the least value below. > 0: each node instead descends a log
  /// barrier over its corners below target whose floor lies `barrier` times the gap to target
  /// below the sweep's least value: every poor corner pulls, the worst the most, so the poor
  /// hexes move together out of the greedy ascent's local optima. The least value may fall (never
  /// to the floor; it may fold a corner when the least value is near 0): follow with a greedy call.
  double barrier = 0.0;
};

/// Per node of the hexes, its longest hex edge (0 for a node in no hex).
std::vector<double> longest_hex_edges(const std::vector<std::array<int, 8>>& hexes, const mesh::Positions& xyz);
/// Per node of the hexes, its shortest hex edge (+∞ for a node in no hex).
std::vector<double> shortest_hex_edges(const std::vector<std::array<int, 8>>& hexes, const mesh::Positions& xyz);

/// Outcome of raise_min_scaled_jacobian.
struct MinQualityReport {
  double min_before = 1.0;  ///< least mesh::hex_scaled_jacobian of the hexes before
  double min_after = 1.0;   ///< and after (never lower)
  int below_before = 0;     ///< hexes below options.target before
  int below_after = 0;      ///< and after
  int sweeps = 0;
  int moves = 0;            ///< accepted node moves
};

/// Raises the least scaled Jacobian (mesh::hex_scaled_jacobian: the 8 corners and the centre, as
/// VTK measures it) of a hex mesh, such as
/// the volumetric map's (§3.4.2, where the thesis only checks every hex), by optimization-based
/// smoothing (Freitag and Plassmann 2000): each free node of a hex below
/// `target` moves, one at a time, along the steepest ascent of the least scaled Jacobian over the
/// corners of its hexes (the least-norm point of the convex hull of the near-least corners'
/// gradients), by the longest trial step that raises that least value; sliding nodes move in their
/// tangent plane and are projected back. A move only raises the least value over the hexes it
/// touches, so the mesh's least value never falls and a folded corner never appears where none
/// was. Deterministic: nodes in id order, no randomness.
/// hexes[h]: 8 node ids, node q at offset (q&1, q>>1&1, q>>2&1); fixed: one flag per node;
/// xyz changed in place. sliding (or null): as untangle_hex_mesh.
/// progress: "grid quality" after every sweep with the fraction of max_sweeps done; throws
/// volspline::Cancelled there if it asks to stop.
MinQualityReport raise_min_scaled_jacobian(const std::vector<std::array<int, 8>>& hexes, const std::vector<char>& fixed,
                                           mesh::Positions& xyz, const MinQualityOptions& options = {},
                                           const SlidingNodes* sliding = nullptr, const Progress& progress = {});

}  // namespace volspline::param
