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
