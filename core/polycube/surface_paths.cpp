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

namespace {

// Per-vertex state of one search, kept between calls on this thread: a search touches a small
// part of a large mesh, so it resets what it touched instead of allocating O(n) per call
// (the T-shape layout traces hundreds of seams on one pants).
struct SearchScratch {
  std::vector<double> distance;  // +∞ where untouched
  std::vector<int> predecessor;  // −1 where untouched
  std::vector<char> settled;     // 0 where untouched
  std::vector<int> touched;

  void prepare(int n) {
    if (static_cast<int>(distance.size()) < n) {
      distance.resize(n, std::numeric_limits<double>::infinity());
      predecessor.resize(n, -1);
      settled.resize(n, 0);
    }
  }
  void touch(int v) {
    if (predecessor[v] < 0 && !settled[v] && distance[v] == std::numeric_limits<double>::infinity())
      touched.push_back(v);
  }
  // The path from the search's source to `end`, then every touched entry reset.
  std::vector<int> finish(int end) {
    std::vector<int> path;
    if (end >= 0) {
      for (int v = end; v != -1; v = predecessor[v]) path.push_back(v);
      std::reverse(path.begin(), path.end());
    }
    for (int v : touched) {
      distance[v] = std::numeric_limits<double>::infinity();
      predecessor[v] = -1;
      settled[v] = 0;
    }
    touched.clear();
    return path;
  }
};

SearchScratch& scratch(int n) {
  thread_local SearchScratch s;
  s.prepare(n);
  return s;
}

// Dijkstra from source to the first settled vertex other than source for which is_target(v)
// holds; vertices enter if unblocked or targets.
template <class IsTarget>
std::vector<int> dijkstra_to(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length, int source,
                             const IsTarget& is_target, const std::vector<char>& blocked,
                             const std::function<bool(int)>& edge_ok) {
  SearchScratch& w = scratch(mesh.num_vertices());
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  w.touch(source);
  w.distance[source] = 0.0;
  queue.push({0.0, source});
  int reached = -1;
  while (!queue.empty()) {
    const auto [d, u] = queue.top();
    queue.pop();
    if (w.settled[u]) continue;
    w.settled[u] = 1;
    if (u != source && is_target(u)) {
      reached = u;
      break;
    }
    for (int h : mesh.vertex_outgoing(u)) {
      const int v = mesh.halfedge_vertex(h);
      if (w.settled[v] || (blocked[v] && !is_target(v))) continue;
      if (edge_ok && !edge_ok(h)) continue;
      const double candidate = d + length[mesh.halfedge_edge(h)];
      if (candidate < w.distance[v]) {
        w.touch(v);
        w.distance[v] = candidate;
        w.predecessor[v] = u;
        queue.push({candidate, v});
      }
    }
  }
  return w.finish(reached);
}

}  // namespace

std::vector<int> path_to_nearest(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length, int source,
                                 const std::vector<char>& is_target, const std::vector<char>& blocked,
                                 const std::function<bool(int)>& edge_ok) {
  return dijkstra_to(mesh, length, source, [&](int v) { return is_target[v] != 0; }, blocked, edge_ok);
}

std::vector<int> restricted_path(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length,
                                 int source, int target, const std::vector<char>& blocked,
                                 const std::function<bool(int)>& edge_ok) {
  return dijkstra_to(mesh, length, source, [target](int v) { return v == target; }, blocked, edge_ok);
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
  SearchScratch& w = scratch(n);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  w.touch(source);
  w.distance[source] = 0.0;
  queue.push({estimate(source), source});
  bool reached = false;
  while (!queue.empty()) {
    const int u = queue.top().second;
    queue.pop();
    if (w.settled[u]) continue;
    w.settled[u] = 1;
    if (u == target && u != source) {
      reached = true;
      break;
    }
    for (int h : mesh.vertex_outgoing(u)) {
      const int v = mesh.halfedge_vertex(h);
      if (w.settled[v] || (blocked[v] && v != target)) continue;
      if (edge_ok && !edge_ok(h)) continue;
      const double candidate = w.distance[u] + length[mesh.halfedge_edge(h)];
      if (candidate < w.distance[v]) {
        w.touch(v);
        w.distance[v] = candidate;
        w.predecessor[v] = u;
        queue.push({candidate + estimate(v), v});
      }
    }
  }
  return w.finish(reached ? target : -1);
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
