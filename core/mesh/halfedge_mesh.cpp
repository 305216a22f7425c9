// SPDX-License-Identifier: MIT
#include "core/mesh/halfedge_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "core/common/error.h"

namespace volspline::mesh {
namespace {

[[noreturn]] void fail(const std::string& source_name, const std::string& what) {
  throw Error("mesh '" + source_name + "': " + what);
}

void check_faces_and_positions(const TriangleMesh& mesh, const std::string& name) {
  const int n = mesh.num_vertices();
  const int m = mesh.num_faces();
  if (m == 0) fail(name, "has no faces");
  for (int f = 0; f < m; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(f, k);
      if (v < 0 || v >= n) {
        fail(name, "face " + std::to_string(f) + " has vertex id " + std::to_string(v) +
                       " out of range [0, " + std::to_string(n) + ")");
      }
    }
    const int a = mesh.triangles(f, 0), b = mesh.triangles(f, 1), c = mesh.triangles(f, 2);
    if (a == b || b == c || c == a) {
      const int repeated = (a == b || a == c) ? a : b;
      fail(name, "face " + std::to_string(f) + " repeats vertex " + std::to_string(repeated) +
                     " (" + std::to_string(a) + ", " + std::to_string(b) + ", " +
                     std::to_string(c) + ")");
    }
  }
  for (int v = 0; v < n; ++v) {
    const auto p = mesh.positions.row(v);
    if (!std::isfinite(p(0)) || !std::isfinite(p(1)) || !std::isfinite(p(2))) {
      std::ostringstream out;
      out << "vertex " << v << " has a non-finite coordinate (" << p(0) << ", " << p(1) << ", "
          << p(2) << ")";
      fail(name, out.str());
    }
  }
}

std::string edge_text(int a, int b) {
  return "(" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
}

// The directed face edges (halfedge h = 3f + k runs from corner k to corner k + 1 of face f)
// grouped by undirected edge: halfedge order[i], i in run_start[e] .. run_start[e + 1] − 1, lie on
// edge e = (lo, hi); edges in lexicographic order.
struct EdgeRuns {
  std::vector<int> lo, hi;  // per halfedge: its smaller and larger endpoint
  std::vector<int> order;
  std::vector<int> run_start;
  int num_edges() const { return static_cast<int>(run_start.size()) - 1; }
  int run_size(int e) const { return run_start[e + 1] - run_start[e]; }
};

// Groups the halfedges by counting sort on the smaller endpoint, then a small sort per bucket on
// (larger endpoint, halfedge id): linear plus tiny sorts. Throws on an edge with more than two
// faces, naming the one whose first face is lowest.
EdgeRuns group_edges(const Triangles& tri, int n, const std::string& source_name) {
  const int num_interior = 3 * static_cast<int>(tri.rows());
  auto source_of = [&](int h) { return tri(h / 3, h % 3); };
  auto tip_of = [&](int h) { return tri(h / 3, (h % 3 + 1) % 3); };
  EdgeRuns edges;
  std::vector<int>& lo = edges.lo;
  std::vector<int>& hi = edges.hi;
  std::vector<int>& order = edges.order;
  lo.resize(num_interior);
  hi.resize(num_interior);
  std::vector<int> bucket_start(n + 1, 0);
  for (int h = 0; h < num_interior; ++h) {
    lo[h] = std::min(source_of(h), tip_of(h));
    hi[h] = std::max(source_of(h), tip_of(h));
    ++bucket_start[lo[h] + 1];
  }
  for (int v = 0; v < n; ++v) bucket_start[v + 1] += bucket_start[v];
  order.resize(num_interior);
  {
    // Keys (larger endpoint, halfedge) packed in 64 bits keep the per-bucket sorts cache-local.
    std::vector<std::uint64_t> keys(num_interior);
    std::vector<int> fill(bucket_start.begin(), bucket_start.end() - 1);
    for (int h = 0; h < num_interior; ++h) {
      keys[fill[lo[h]]++] = (static_cast<std::uint64_t>(hi[h]) << 32) | static_cast<std::uint32_t>(h);
    }
    for (int v = 0; v < n; ++v) {
      std::sort(keys.begin() + bucket_start[v], keys.begin() + bucket_start[v + 1]);
    }
    for (int i = 0; i < num_interior; ++i) order[i] = static_cast<int>(keys[i] & 0xffffffffu);
  }

  // Runs of equal (lo, hi) are edges.
  std::vector<int>& run_start = edges.run_start;
  run_start.reserve(num_interior / 2 + 2);
  int worst_run = -1;
  for (int i = 0; i < num_interior;) {
    int j = i + 1;
    while (j < num_interior && lo[order[j]] == lo[order[i]] && hi[order[j]] == hi[order[i]]) ++j;
    if (j - i > 2 && (worst_run < 0 || order[i] < order[worst_run])) worst_run = i;
    run_start.push_back(i);
    i = j;
  }
  run_start.push_back(num_interior);
  if (worst_run >= 0) {
    const int r = static_cast<int>(
        std::lower_bound(run_start.begin(), run_start.end(), worst_run) - run_start.begin());
    const int count = run_start[r + 1] - run_start[r];
    const int h = order[worst_run];
    fail(source_name, "edge " + edge_text(lo[h], hi[h]) + " is shared by " +
                          std::to_string(count) + " faces (first: " +
                          std::to_string(order[worst_run] / 3) + ", " +
                          std::to_string(order[worst_run + 1] / 3) + ", " +
                          std::to_string(order[worst_run + 2] / 3) + ")");
  }
  return edges;
}

// Per face 1 where it must be flipped to agree with its neighbours: breadth-first orientation
// propagation per edge-connected component, seeded at its lowest face (kept as it is). Throws
// when a contradiction shows the surface is not orientable.
std::vector<char> consistent_flips(const Triangles& tri, const EdgeRuns& edges, const std::string& source_name) {
  const int m = static_cast<int>(tri.rows());
  const int num_interior = 3 * m;
  // Provisional twins on the input orientation; same_direction marks two faces using the same
  // directed edge, which one of them must be flipped to fix.
  std::vector<int> mate(num_interior, no_id);
  std::vector<char> same_direction(num_interior, 0);
  for (int e = 0; e < edges.num_edges(); ++e) {
    if (edges.run_size(e) != 2) continue;
    const int a = edges.order[edges.run_start[e]], b = edges.order[edges.run_start[e] + 1];
    mate[a] = b;
    mate[b] = a;
    same_direction[a] = same_direction[b] = tri(a / 3, a % 3) == tri(b / 3, b % 3);
  }
  std::vector<char> flipped(m, 0);
  std::vector<char> visited(m, 0);
  std::vector<int> queue;
  queue.reserve(m);
  for (int seed = 0; seed < m; ++seed) {
    if (visited[seed]) continue;
    visited[seed] = 1;
    queue.assign(1, seed);
    for (size_t q = 0; q < queue.size(); ++q) {
      const int f = queue[q];
      for (int k = 0; k < 3; ++k) {
        const int h = 3 * f + k;
        if (mate[h] == no_id) continue;
        const int g = mate[h] / 3;
        const char want = flipped[f] ^ same_direction[h];
        if (!visited[g]) {
          visited[g] = 1;
          flipped[g] = want;
          queue.push_back(g);
        } else if (flipped[g] != want) {
          fail(source_name, "the surface is not orientable: faces " + std::to_string(f) +
                                " and " + std::to_string(g) + " at edge " +
                                edge_text(edges.lo[h], edges.hi[h]) +
                                " cannot be oriented consistently with their neighbours");
        }
      }
    }
  }
  return flipped;
}

// Vertex manifoldness: walks each fan of interior halfedges once, in both directions, starting
// from the lowest outgoing halfedge not yet visited. Returns the fans per vertex; sets
// vertex_halfedge[v] to the first halfedge of v's fan where v has exactly one.
std::vector<int> vertex_fans(const Triangles& t, const std::vector<int>& next, const std::vector<int>& prev,
                             const std::vector<int>& twin, std::vector<int>& vertex_halfedge) {
  const int num_interior = 3 * static_cast<int>(t.rows());
  auto is_boundary = [&](int h) { return h >= num_interior; };
  auto rotate_ccw = [&](int h) { return twin[prev[h]]; };
  auto rotate_cw = [&](int h) { return next[twin[h]]; };
  std::vector<int> fan_count(vertex_halfedge.size(), 0);
  std::vector<char> seen(num_interior, 0);
  for (int h0 = 0; h0 < num_interior; ++h0) {
    if (seen[h0]) continue;
    const int v = t(h0 / 3, h0 % 3);
    ++fan_count[v];
    seen[h0] = 1;
    int h = rotate_ccw(h0);
    while (!is_boundary(h) && h != h0) {
      seen[h] = 1;
      h = rotate_ccw(h);
    }
    int first = h0;
    if (is_boundary(h)) {
      while (!is_boundary(twin[first])) {
        first = rotate_cw(first);
        seen[first] = 1;
      }
    }
    if (fan_count[v] == 1) vertex_halfedge[v] = first;
  }
  return fan_count;
}

}  // namespace

HalfedgeMesh HalfedgeMesh::build(const TriangleMesh& input, const std::string& source_name) {
  check_faces_and_positions(input, source_name);
  const int n = input.num_vertices();
  const int m = input.num_faces();
  const int num_interior = 3 * m;
  const EdgeRuns edges = group_edges(input.triangles, n, source_name);
  const int num_edges = edges.num_edges();

  HalfedgeMesh result;
  result.source_name_ = source_name;
  result.flipped_ = consistent_flips(input.triangles, edges, source_name);
  result.positions_ = input.positions;
  result.triangles_ = input.triangles;
  for (int f = 0; f < m; ++f) {
    if (!result.flipped_[f]) continue;
    ++result.num_flipped_faces_;
    std::swap(result.triangles_(f, 1), result.triangles_(f, 2));
  }
  // Reversing (c0, c1, c2) to (c0, c2, c1) maps old halfedge k onto new halfedge 2 - k.
  auto remap = [&](int h) { return result.flipped_[h / 3] ? 3 * (h / 3) + 2 - h % 3 : h; };

  const int num_halfedges = 2 * num_edges;
  const Triangles& t = result.triangles_;
  result.next_.resize(num_halfedges);
  result.prev_.resize(num_halfedges);
  result.twin_.resize(num_halfedges);
  result.vertex_.resize(num_halfedges);
  result.edge_.resize(num_halfedges);
  result.edge_halfedge_.resize(num_edges);
  for (int h = 0; h < num_interior; ++h) {
    const int f = h / 3, k = h % 3;
    result.next_[h] = 3 * f + (k + 1) % 3;
    result.prev_[h] = 3 * f + (k + 2) % 3;
    result.vertex_[h] = t(f, (k + 1) % 3);
  }
  int next_boundary = num_interior;
  for (int e = 0; e < num_edges; ++e) {
    const int a = remap(edges.order[edges.run_start[e]]);
    int b;
    if (edges.run_size(e) == 2) {
      b = remap(edges.order[edges.run_start[e] + 1]);
    } else {
      b = next_boundary++;
      result.vertex_[b] = t(a / 3, a % 3);
    }
    result.twin_[a] = b;
    result.twin_[b] = a;
    result.edge_[a] = result.edge_[b] = e;
    result.edge_halfedge_[e] = std::min(a, b);
  }

  result.vertex_halfedge_.assign(n, no_id);
  const std::vector<int> fan_count = vertex_fans(t, result.next_, result.prev_, result.twin_, result.vertex_halfedge_);
  for (int v = 0; v < n; ++v) {
    if (fan_count[v] > 1) {
      fail(source_name, "vertex " + std::to_string(v) + " is non-manifold: its faces form " +
                            std::to_string(fan_count[v]) + " separate fans");
    }
    if (fan_count[v] == 0) ++result.num_unreferenced_vertices_;
  }

  // Boundary loops: each boundary vertex now has exactly one outgoing boundary halfedge.
  std::vector<int> boundary_out(n, no_id);
  for (int b = num_interior; b < num_halfedges; ++b) boundary_out[result.vertex_[result.twin_[b]]] = b;
  for (int b = num_interior; b < num_halfedges; ++b) {
    const int after = boundary_out[result.vertex_[b]];
    result.next_[b] = after;
    result.prev_[after] = b;
  }
  return result;
}

int HalfedgeMesh::vertex_valence(int v) const {
  int count = 0;
  for (int h : vertex_outgoing(v)) {
    (void)h;
    ++count;
  }
  return count;
}

}  // namespace volspline::mesh
