// SPDX-License-Identifier: MIT
#include "core/mesh/graph_distance.h"

#include <algorithm>
#include <cassert>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "core/mesh/mesh_geometry.h"

namespace volspline::mesh {

GraphDistances graph_distances(const HalfedgeMesh& mesh, const std::vector<int>& sources) {
  return graph_distances(mesh, sources, edge_lengths(mesh));
}

GraphDistances graph_distances(const HalfedgeMesh& mesh, const std::vector<int>& sources,
                               const std::vector<double>& edge_lengths) {
  assert(static_cast<int>(edge_lengths.size()) == mesh.num_edges());
  const int n = mesh.num_vertices();
  GraphDistances result;
  result.distance.assign(n, std::numeric_limits<double>::infinity());
  result.predecessor.assign(n, no_id);
  result.nearest_source.assign(n, -1);

  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (int i = 0; i < static_cast<int>(sources.size()); ++i) {
    const int s = sources[i];
    assert(s >= 0 && s < n);
    if (result.nearest_source[s] >= 0) continue;
    result.distance[s] = 0.0;
    result.nearest_source[s] = i;
    queue.push({0.0, s});
  }
  std::vector<char> settled(n, 0);
  while (!queue.empty()) {
    const auto [d, u] = queue.top();
    queue.pop();
    if (settled[u] || d > result.distance[u]) continue;
    settled[u] = 1;
    for (int h : mesh.vertex_outgoing(u)) {
      const int v = mesh.halfedge_vertex(h);
      if (settled[v]) continue;
      const double length = edge_lengths[mesh.halfedge_edge(h)];
      assert(length >= 0.0);
      const double candidate = d + length;
      if (candidate < result.distance[v] ||
          (candidate == result.distance[v] && u < result.predecessor[v])) {
        const bool improved = candidate < result.distance[v];
        result.distance[v] = candidate;
        result.predecessor[v] = u;
        result.nearest_source[v] = result.nearest_source[u];
        if (improved) queue.push({candidate, v});
      }
    }
  }
  return result;
}

std::vector<int> graph_path(const GraphDistances& distances, int target) {
  std::vector<int> path;
  if (distances.nearest_source[target] < 0) return path;
  for (int v = target; v != no_id; v = distances.predecessor[v]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace volspline::mesh
