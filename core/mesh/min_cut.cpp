// SPDX-License-Identifier: MIT
#include "core/mesh/min_cut.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace volspline::mesh {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

}  // namespace

MinCut::MinCut(int num_nodes) : head_(num_nodes, -1), level_(num_nodes), current_(num_nodes), reached_(num_nodes, 0) {}

void MinCut::add_arc(int a, int b, double forward, double backward) {
  assert(a >= 0 && b >= 0 && a != b && a < static_cast<int>(head_.size()) && b < static_cast<int>(head_.size()));
  assert(forward >= 0.0 && backward >= 0.0);
  // Arcs 2k and 2k + 1 are each other's reverse.
  to_.push_back(b);
  residual_.push_back(forward);
  next_.push_back(head_[a]);
  head_[a] = static_cast<int>(to_.size()) - 1;
  to_.push_back(a);
  residual_.push_back(backward);
  next_.push_back(head_[b]);
  head_[b] = static_cast<int>(to_.size()) - 1;
}

bool MinCut::levels_from(int source, int sink) {
  std::fill(level_.begin(), level_.end(), -1);
  std::vector<int> queue{source};
  level_[source] = 0;
  for (std::size_t i = 0; i < queue.size(); ++i) {
    const int u = queue[i];
    for (int a = head_[u]; a >= 0; a = next_[a])
      if (residual_[a] > 0.0 && level_[to_[a]] < 0) {
        level_[to_[a]] = level_[u] + 1;
        queue.push_back(to_[a]);
      }
  }
  return level_[sink] >= 0;
}

double MinCut::augment_blocking(int source, int sink) {
  // Iterative depth-first search along level-increasing arcs (paths may be long: no recursion).
  double total = 0.0;
  std::vector<int> path;  // arcs from the source
  int u = source;
  for (;;) {
    if (u == sink) {
      double push = kInfinity;
      for (int a : path) push = std::min(push, residual_[a]);
      if (std::isinf(push)) return kInfinity;
      total += push;
      std::size_t back = path.size();
      for (std::size_t i = 0; i < path.size(); ++i) {
        residual_[path[i]] -= push;
        residual_[path[i] ^ 1] += push;
        if (residual_[path[i]] <= 0.0 && back == path.size()) back = i;
      }
      path.resize(back);
      u = path.empty() ? source : to_[path.back()];
      continue;
    }
    int& a = current_[u];
    while (a >= 0 && !(residual_[a] > 0.0 && level_[to_[a]] == level_[u] + 1)) a = next_[a];
    if (a >= 0) {
      path.push_back(a);
      u = to_[a];
      continue;
    }
    // Dead end: no path to the sink from u in this phase.
    level_[u] = -1;
    if (path.empty()) return total;
    path.pop_back();
    u = path.empty() ? source : to_[path.back()];
    current_[u] = next_[current_[u]];
  }
}

double MinCut::solve(int source, int sink) {
  assert(source != sink);
  double flow = 0.0;
  while (levels_from(source, sink)) {
    for (std::size_t u = 0; u < head_.size(); ++u) current_[u] = head_[u];
    const double pushed = augment_blocking(source, sink);
    if (std::isinf(pushed)) {
      flow = kInfinity;
      break;
    }
    flow += pushed;
    if (!(pushed > 0.0)) break;
  }
  std::fill(reached_.begin(), reached_.end(), 0);
  std::vector<int> queue{source};
  reached_[source] = 1;
  for (std::size_t i = 0; i < queue.size(); ++i)
    for (int a = head_[queue[i]]; a >= 0; a = next_[a])
      if (residual_[a] > 0.0 && !reached_[to_[a]]) {
        reached_[to_[a]] = 1;
        queue.push_back(to_[a]);
      }
  return flow;
}

}  // namespace volspline::mesh
