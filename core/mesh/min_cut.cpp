// SPDX-License-Identifier: MIT
#include "core/mesh/min_cut.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <deque>
#include <limits>
#include <utility>
#include <vector>

namespace volspline::mesh {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

}  // namespace

MinCut::MinCut(int num_nodes) : head_(num_nodes, -1), label_(num_nodes), current_(num_nodes), reached_(num_nodes, 0) {}

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

// Labels from the sink: breadth-first over the arcs with residual capacity, walked backwards
// (arc b leaves y, its pair b ^ 1 enters y from to_[b]); unreached nodes get n (no path).
void MinCut::global_relabel(int sink) {
  const int n = static_cast<int>(head_.size());
  std::fill(label_.begin(), label_.end(), n);
  label_[sink] = 0;
  queue_.assign(1, sink);
  for (std::size_t i = 0; i < queue_.size(); ++i) {
    const int y = queue_[i];
    for (int b = head_[y]; b >= 0; b = next_[b]) {
      const int x = to_[b];
      if (label_[x] == n && residual_[b ^ 1] > 0.0) {
        label_[x] = label_[y] + 1;
        queue_.push_back(x);
      }
    }
  }
}

double MinCut::solve(int source, int sink) {
  assert(source != sink);
  const int n = static_cast<int>(head_.size());
  // The minimum cut closest to the source, which every maximum flow leaves reachable from it:
  // computed on the reversed network (each pair's capacities swapped, sink and source exchanged),
  // whose maximum preflow (push–relabel, Goldberg & Tarjan 1988: FIFO, global relabelling) leaves
  // that set as the nodes that can still reach the reversed sink. Capacities are exact multiples
  // of a power of two where the callers quantize them, so the set does not depend on the algorithm.
  // Infinite capacities become one more than twice all finite ones: a flow that large means no
  // finite cut.
  double finite = 0.0;
  for (double& r : residual_)
    if (!std::isinf(r)) finite += r;
  const double big = 2.0 * finite + 1.0;
  for (double& r : residual_)
    if (std::isinf(r)) r = big;
  for (std::size_t a = 0; a < residual_.size(); a += 2) std::swap(residual_[a], residual_[a + 1]);
  const int top = sink, bottom = source;  // the reversed network's source and sink
  excess_.assign(n, 0.0);
  label_.resize(n);
  global_relabel(bottom);
  label_[top] = n;
  std::deque<int> active;  // FIFO
  std::vector<char> queued(n, 0);
  for (int a = head_[top]; a >= 0; a = next_[a]) {
    const double push = residual_[a];
    if (!(push > 0.0)) continue;
    residual_[a] = 0.0;
    residual_[a ^ 1] += push;
    const int v = to_[a];
    excess_[v] += push;
    if (v != bottom && !queued[v]) queued[v] = 1, active.push_back(v);
  }
  for (int u = 0; u < n; ++u) current_[u] = head_[u];
  long work = 0;
  const long relabel_every = 6L * n + static_cast<long>(to_.size()) / 2;
  while (!active.empty()) {
    const int u = active.front();
    active.pop_front();
    queued[u] = 0;
    if (work > relabel_every) {
      work = 0;
      const int kept = label_[top];
      global_relabel(bottom);
      label_[top] = kept;
      for (int v = 0; v < n; ++v) current_[v] = head_[v];
    }
    // Discharge u: push along admissible arcs, relabel when none is left, until its excess is
    // gone or it cannot reach the sink any more (label n: its excess stays on the source side).
    while (excess_[u] > 0.0 && label_[u] < n) {
      int& a = current_[u];
      if (a < 0) {
        int least = 2 * n;
        for (int b = head_[u]; b >= 0; b = next_[b])
          if (residual_[b] > 0.0) least = std::min(least, label_[to_[b]]);
        label_[u] = std::min(n, least + 1);
        a = head_[u];
        work += 12;
        continue;
      }
      const int v = to_[a];
      if (residual_[a] > 0.0 && label_[u] == label_[v] + 1) {
        const double push = std::min(excess_[u], residual_[a]);
        residual_[a] -= push;
        residual_[a ^ 1] += push;
        excess_[u] -= push;
        excess_[v] += push;
        if (v != top && v != bottom && !queued[v]) queued[v] = 1, active.push_back(v);
        if (excess_[u] > 0.0) a = next_[a];
      } else {
        a = next_[a];
      }
      ++work;
    }
  }
  // The nodes that can reach the reversed sink (the original source) in the residual network.
  std::fill(reached_.begin(), reached_.end(), 0);
  reached_[bottom] = 1;
  queue_.assign(1, bottom);
  for (std::size_t i = 0; i < queue_.size(); ++i)
    for (int b = head_[queue_[i]]; b >= 0; b = next_[b])
      if (!reached_[to_[b]] && residual_[b ^ 1] > 0.0) {
        reached_[to_[b]] = 1;
        queue_.push_back(to_[b]);
      }
  const double flow = excess_[bottom];
  return flow >= big ? kInfinity : flow;
}

}  // namespace volspline::mesh
