// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/mesh/min_cut.h"

using volspline::mesh::MinCut;

TEST_CASE("min cut: the textbook network has flow 23 and the cut {s, v1, v2, v4}") {
  // s = 0, v1..v4 = 1..4, t = 5 (Cormen et al., Fig. 26.1).
  MinCut g(6);
  g.add_arc(0, 1, 16, 0);
  g.add_arc(0, 2, 13, 0);
  g.add_arc(1, 3, 12, 0);
  g.add_arc(2, 1, 4, 0);
  g.add_arc(2, 4, 14, 0);
  g.add_arc(3, 2, 9, 0);
  g.add_arc(3, 5, 20, 0);
  g.add_arc(4, 3, 7, 0);
  g.add_arc(4, 5, 4, 0);
  CHECK(g.solve(0, 5) == 23.0);
  CHECK(g.source_side() == std::vector<char>{1, 1, 1, 0, 1, 0});
}

TEST_CASE("min cut: undirected arcs in series and in parallel; an infinite path is never cut") {
  // 0 – 1 – 3 (capacities 2, 5) and 0 – 2 – 3 (capacities 4, 1): the cut takes 2 and 1.
  MinCut g(4);
  g.add_arc(0, 1, 2, 2);
  g.add_arc(1, 3, 5, 5);
  g.add_arc(0, 2, 4, 4);
  g.add_arc(2, 3, 1, 1);
  CHECK(g.solve(0, 3) == 3.0);
  CHECK(g.source_side() == std::vector<char>{1, 0, 1, 0});

  const double inf = std::numeric_limits<double>::infinity();
  MinCut h(3);
  h.add_arc(0, 1, inf, 0);
  h.add_arc(1, 2, inf, 0);
  h.add_arc(0, 2, 1, 0);
  CHECK(std::isinf(h.solve(0, 2)));

  // A long chain (no recursion limit): its weakest arc.
  const int n = 200000;
  MinCut chain(n);
  for (int i = 0; i + 1 < n; ++i) chain.add_arc(i, i + 1, i == n / 2 ? 0.5 : 1.0, 0.0);
  CHECK(chain.solve(0, n - 1) == 0.5);
  CHECK(chain.source_side()[n / 2] == 1);
  CHECK(chain.source_side()[n / 2 + 1] == 0);
}

namespace {

// Reference for the test below: Edmonds–Karp (shortest augmenting paths, one at a time) on a
// dense capacity matrix, then the nodes reachable from the source in the residual network.
double reference_min_cut(std::vector<std::vector<double>> c, int s, int t, std::vector<char>& side) {
  const int n = static_cast<int>(c.size());
  double flow = 0.0;
  for (;;) {
    std::vector<int> parent(n, -1);
    parent[s] = s;
    std::vector<int> queue{s};
    for (std::size_t i = 0; i < queue.size() && parent[t] < 0; ++i)
      for (int v = 0; v < n; ++v)
        if (parent[v] < 0 && c[queue[i]][v] > 0.0) parent[v] = queue[i], queue.push_back(v);
    if (parent[t] < 0) break;
    double push = std::numeric_limits<double>::infinity();
    for (int v = t; v != s; v = parent[v]) push = std::min(push, c[parent[v]][v]);
    for (int v = t; v != s; v = parent[v]) c[parent[v]][v] -= push, c[v][parent[v]] += push;
    flow += push;
  }
  side.assign(n, 0);
  side[s] = 1;
  std::vector<int> queue{s};
  for (std::size_t i = 0; i < queue.size(); ++i)
    for (int v = 0; v < n; ++v)
      if (!side[v] && c[queue[i]][v] > 0.0) side[v] = 1, queue.push_back(v);
  return flow;
}

}  // namespace

TEST_CASE("min cut: random networks with many tied cuts give the flow and the cut closest to the source") {
  // Small integer capacities make many minimum cuts; the one every maximum flow leaves reachable
  // from the source is unique, whatever algorithm finds the flow.
  unsigned state = 12345u;
  auto next = [&](unsigned m) {
    state = state * 1664525u + 1013904223u;
    return (state >> 8) % m;
  };
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 3 + static_cast<int>(next(30));
    std::vector<std::vector<double>> c(n, std::vector<double>(n, 0.0));
    MinCut g(n);
    const int arcs = n + static_cast<int>(next(4 * n));
    for (int k = 0; k < arcs; ++k) {
      const int a = static_cast<int>(next(n)), b = static_cast<int>(next(n));
      if (a == b) continue;
      const double f = static_cast<double>(next(4)), r = next(2) ? f : static_cast<double>(next(3));
      g.add_arc(a, b, f, r);
      c[a][b] += f;
      c[b][a] += r;
    }
    std::vector<char> side;
    const double want = reference_min_cut(c, 0, n - 1, side);
    CHECK(g.solve(0, n - 1) == want);
    CHECK(g.source_side() == side);
  }
}
