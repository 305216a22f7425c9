// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

namespace volspline::mesh {

/// A minimum s–t cut of a graph with non-negative real capacities (push–relabel).
/// Build with add_arc, then call solve once.
class MinCut {
 public:
  /// `num_nodes` nodes, no arcs.
  explicit MinCut(int num_nodes);

  /// An arc a → b of capacity `forward` and one b → a of capacity `backward` (each ≥ 0; +infinity
  /// allowed: such an arc is never cut). Preconditions (assert): a, b node ids, a ≠ b.
  void add_arc(int a, int b, double forward, double backward);

  /// Maximum flow from `source` to `sink` (= the capacity of a minimum cut; +infinity when every
  /// cut holds an infinite arc). Deterministic: arcs are scanned in insertion order.
  double solve(int source, int sink);

  /// After solve: per node, 1 if it lies on the source side of the minimum cut closest to the
  /// source (the nodes any maximum flow leaves reachable from the source in the residual graph:
  /// unique, so independent of the algorithm when the capacities add up exactly, e.g. multiples
  /// of one power of two), else 0.
  const std::vector<char>& source_side() const { return reached_; }

 private:
  void global_relabel(int sink);

  std::vector<int> head_, next_, to_, label_, current_, queue_;
  std::vector<double> residual_, excess_;
  std::vector<char> reached_;
};

}  // namespace volspline::mesh
