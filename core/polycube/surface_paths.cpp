// SPDX-License-Identifier: MIT
#include "core/polycube/surface_paths.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <queue>
#include <utility>

namespace volspline::polycube {

int edge_between(const mesh::HalfedgeMesh& mesh, int a, int b) {
  for (int h : mesh.vertex_outgoing(a))
    if (mesh.halfedge_vertex(h) == b) return mesh.halfedge_edge(h);
  return -1;
}

std::vector<int> path_to_nearest(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length, int source,
                                 const std::vector<char>& is_target, const std::vector<char>& blocked,
                                 const std::function<bool(int)>& edge_ok) {
  const int n = mesh.num_vertices();
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<int> predecessor(n, -1);
  std::vector<char> settled(n, 0);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  distance[source] = 0.0;
  queue.push({0.0, source});
  int reached = -1;
  while (!queue.empty()) {
    const auto [d, u] = queue.top();
    queue.pop();
    if (settled[u]) continue;
    settled[u] = 1;
    if (u != source && is_target[u]) {
      reached = u;
      break;
    }
    for (int h : mesh.vertex_outgoing(u)) {
      const int v = mesh.halfedge_vertex(h);
      if (settled[v] || (blocked[v] && !is_target[v])) continue;
      if (edge_ok && !edge_ok(h)) continue;
      const double candidate = d + length[mesh.halfedge_edge(h)];
      if (candidate < distance[v]) {
        distance[v] = candidate;
        predecessor[v] = u;
        queue.push({candidate, v});
      }
    }
  }
  std::vector<int> path;
  if (reached < 0) return path;
  for (int v = reached; v != -1; v = predecessor[v]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

std::vector<int> restricted_path(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length,
                                 int source, int target, const std::vector<char>& blocked,
                                 const std::function<bool(int)>& edge_ok) {
  std::vector<char> is_target(mesh.num_vertices(), 0);
  is_target[target] = 1;
  return path_to_nearest(mesh, length, source, is_target, blocked, edge_ok);
}

double straight_line_bound(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length) {
  double bound = 1.0;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const int h = mesh.edge_halfedge(e);
    const double straight = (mesh.vertex_position(mesh.halfedge_vertex(h)) -
                             mesh.vertex_position(mesh.halfedge_vertex(mesh.halfedge_twin(h))))
                                .norm();
    if (straight > 0.0) bound = std::min(bound, length[e] / straight);
  }
  return std::max(bound, 0.0);
}

std::vector<int> guided_path(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length, double bound,
                             int source, int target, const std::vector<char>& blocked,
                             const std::function<bool(int)>& edge_ok) {
  const int n = mesh.num_vertices();
  const Eigen::Vector3d goal = mesh.vertex_position(target);
  // The margin keeps the estimate consistent through the rounding of the distances.
  const double scale = bound * (1.0 - 1e-9);
  auto estimate = [&](int v) { return scale * (mesh.vertex_position(v) - goal).norm(); };
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<int> predecessor(n, -1);
  std::vector<char> settled(n, 0);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  distance[source] = 0.0;
  queue.push({estimate(source), source});
  bool reached = false;
  while (!queue.empty()) {
    const int u = queue.top().second;
    queue.pop();
    if (settled[u]) continue;
    settled[u] = 1;
    if (u == target && u != source) {
      reached = true;
      break;
    }
    for (int h : mesh.vertex_outgoing(u)) {
      const int v = mesh.halfedge_vertex(h);
      if (settled[v] || (blocked[v] && v != target)) continue;
      if (edge_ok && !edge_ok(h)) continue;
      const double candidate = distance[u] + length[mesh.halfedge_edge(h)];
      if (candidate < distance[v]) {
        distance[v] = candidate;
        predecessor[v] = u;
        queue.push({candidate + estimate(v), v});
      }
    }
  }
  std::vector<int> path;
  if (!reached) return path;
  for (int v = target; v != -1; v = predecessor[v]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

int face_components(const mesh::HalfedgeMesh& mesh, const std::vector<char>& cut_edge,
                    std::vector<int>& component) {
  component.assign(mesh.num_faces(), -1);
  int count = 0;
  std::vector<int> stack;
  for (int seed = 0; seed < mesh.num_faces(); ++seed) {
    if (component[seed] >= 0) continue;
    component[seed] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      for (int h : mesh.face_halfedges(f)) {
        if (cut_edge[mesh.halfedge_edge(h)]) continue;
        const int g = mesh.halfedge_face(mesh.halfedge_twin(h));
        if (g >= 0 && component[g] < 0) {
          component[g] = count;
          stack.push_back(g);
        }
      }
    }
    ++count;
  }
  return count;
}

void mark_path_edges(const mesh::HalfedgeMesh& mesh, const std::vector<int>& path,
                     std::vector<char>& cut_edge) {
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const int e = edge_between(mesh, path[i], path[i + 1]);
    assert(e >= 0);
    cut_edge[e] = 1;
  }
}

}  // namespace volspline::polycube
