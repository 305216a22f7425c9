// SPDX-License-Identifier: MIT
#include "core/polycube/cut_tightening.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <queue>
#include <set>

#include "core/mesh/graph_distance.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_lists.h"
#include "core/mesh/min_cut.h"
#include "core/polycube/interface_disc.h"

namespace volspline::polycube {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kMinGain = 0.95;  // a new loop must be at least 5 % shorter
// A cap's cut moves only off a diagonal level set: to a loop at least 15 % shorter (the band
// around it: see tighten_cut_loops).
constexpr double kCapGain = 0.85;

// χ = V − E + F of a face set must be 2 − (its boundary loops) for a planar piece.
bool planar_with_loops(const mesh::HalfedgeMesh& hm, const std::vector<int>& face_piece, int piece, int loops) {
  std::set<int> verts;
  long faces = 0, edges2 = 0;
  for (int f = 0; f < hm.num_faces(); ++f) {
    if (face_piece[f] != piece) continue;
    ++faces;
    for (int v : hm.face_vertices(f)) verts.insert(v);
    for (int h : hm.face_halfedges(f)) edges2 += face_piece[hm.halfedge_face(hm.halfedge_twin(h))] == piece ? 1 : 2;
  }
  return static_cast<long>(verts.size()) - edges2 / 2 + faces == 2 - loops;
}

// Marks the faces of `piece` on a shortest dual path (face centroids) from a face with
// `is_seed` to one with `is_target`, crossing no edge in `blocked` (undirected vertex pairs), so
// that two boundaries form one terminal.
void mark_joining_path(const mesh::HalfedgeMesh& hm, const std::vector<int>& face_piece, int piece,
                       const std::function<bool(int)>& is_seed, const std::function<bool(int)>& is_target,
                       const std::set<std::pair<int, int>>& blocked, std::vector<char>& mark) {
  auto centroid = [&](int f) {
    Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
    for (int v : hm.face_vertices(f)) c += hm.positions().row(v);
    return Eigen::RowVector3d(c / 3.0);
  };
  std::vector<double> dist(hm.num_faces(), kInfinity);
  std::vector<int> pred(hm.num_faces(), -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (int f = 0; f < hm.num_faces(); ++f)
    if (face_piece[f] == piece && is_seed(f)) {
      dist[f] = 0.0;
      queue.push({0.0, f});
    }
  while (!queue.empty()) {
    const auto [df, f] = queue.top();
    queue.pop();
    if (df > dist[f]) continue;
    if (is_target(f)) {
      for (int g = f; g >= 0; g = pred[g]) mark[g] = 1;
      return;
    }
    for (int h : hm.face_halfedges(f)) {
      const int g = hm.halfedge_face(hm.halfedge_twin(h));
      const int u = hm.halfedge_source(h), v = hm.halfedge_vertex(h);
      if (g < 0 || face_piece[g] != piece || blocked.count({std::min(u, v), std::max(u, v)})) continue;
      const double dg = df + (centroid(f) - centroid(g)).norm();
      if (dg < dist[g]) {
        dist[g] = dg;
        pred[g] = f;
        queue.push({dg, g});
      }
    }
  }
}

// The shortest loop replacing cut `l`, oriented with the piece below on its left; empty if there
// is none better or it is not one simple loop. `below` gets, per region face, 1 on the side of
// the piece below.
std::vector<int> shortest_loop(const mesh::HalfedgeMesh& hm, const SolidDecomposition& d,
                               const std::vector<int>& face_piece, const std::vector<int>& vertex_loop, int l,
                               const std::vector<double>& distance, double radius, double quantum,
                               std::vector<std::pair<int, char>>& below) {
  const CutLoop& loop = d.loops[l];
  const int a = loop.piece[0], b = loop.piece[1];
  const bool self = a == b;
  // Terminals: the other loops of each side (two different pieces), or the two sides of the loop
  // itself (a tube closed on itself, cut open along it).
  std::vector<char> other_a(d.loops.size(), 0), other_b(d.loops.size(), 0);
  bool has_a = false, has_b = false;
  if (!self) {
    for (const LoopSide& s : d.pieces[a].boundary)
      if (s.loop != l) has_a = (other_a[s.loop] = 1);
    for (const LoopSide& s : d.pieces[b].boundary)
      if (s.loop != l) has_b = (other_b[s.loop] = 1);
    // A cap's side has no other loop: only a band's rim on that side can be its terminal.
    if ((!has_a || !has_b) && std::isinf(radius)) return {};
  }
  // Two other loops on one side are joined by a path of that side's faces: the terminals are
  // then connected, the minimum cut is one loop, and it stays disjoint from the path as the cut
  // is, so it is isotopic to the cut (not a loop around each boundary apart).
  // A loop with both sides on one side (a handle through that piece) is two boundaries: the
  // union is cut open along it and its two sides are joined the same way; otherwise the pair of
  // parallel copies of it around its band would be a shorter separator.
  std::vector<char> joined(hm.num_faces(), 0);
  std::set<std::pair<int, int>> open_edges;  // undirected edges of such loops
  if (!self)
    for (int p : {a, b}) {
      std::vector<int> others;
      for (const LoopSide& s : d.pieces[p].boundary)
        if (s.loop != l && std::find(others.begin(), others.end(), s.loop) == others.end()) others.push_back(s.loop);
      auto touches = [&](int f, int m) {
        for (int v : hm.face_vertices(f))
          if (vertex_loop[v] == m) return true;
        return false;
      };
      if (others.size() == 2) {
        mark_joining_path(hm, face_piece, p, [&](int f) { return touches(f, others[0]); },
                          [&](int f) { return touches(f, others[1]); }, {}, joined);
      } else if (others.size() == 1 && d.loops[others[0]].piece[0] == d.loops[others[0]].piece[1]) {
        const std::vector<int>& mv = d.loops[others[0]].vertices;
        std::set<std::pair<int, int>> directed, blocked;
        for (std::size_t i = 0; i < mv.size(); ++i) {
          const int x = mv[i], y = mv[(i + 1) % mv.size()];
          directed.insert({x, y});
          blocked.insert({std::min(x, y), std::max(x, y)});
        }
        auto on_side = [&](int f, bool left) {
          for (int h : hm.face_halfedges(f)) {
            const int u = hm.halfedge_source(h), v = hm.halfedge_vertex(h);
            if (left ? directed.count({u, v}) : directed.count({v, u})) return true;
          }
          return false;
        };
        mark_joining_path(hm, face_piece, p, [&](int f) { return on_side(f, true); },
                          [&](int f) { return on_side(f, false); }, blocked, joined);
        open_edges.insert(blocked.begin(), blocked.end());
      }
    }
  // The region: both pieces, or their band within `radius` of the loop (then its rim on each side
  // is a terminal too, so that the loop can move but not shrink onto another boundary).
  auto in_band = [&](int f) {
    if (face_piece[f] != a && face_piece[f] != b) return false;
    for (int v : hm.face_vertices(f))
      if (!(distance[v] <= radius)) return false;
    return true;
  };
  std::vector<int> node(hm.num_faces(), -1);
  std::vector<int> faces;
  for (int f = 0; f < hm.num_faces(); ++f)
    if (in_band(f)) {
      node[f] = static_cast<int>(faces.size());
      faces.push_back(f);
    }
  const int n = static_cast<int>(faces.size());
  const int source = n, sink = n + 1;
  mesh::MinCut cut(n + 2);
  // The loop's own edges, directed with the piece below on the left.
  std::set<std::pair<int, int>> seam;
  for (std::size_t i = 0; i < loop.vertices.size(); ++i)
    seam.insert({loop.vertices[i], loop.vertices[(i + 1) % loop.vertices.size()]});
  auto on_other_loop = [&](int v) { return vertex_loop[v] >= 0 && vertex_loop[v] != l; };
  for (int f : faces) {
    bool to_source = false, to_sink = false;
    for (int h : hm.face_halfedges(f)) {
      const int u = hm.halfedge_source(h), v = hm.halfedge_vertex(h);
      const int g = hm.halfedge_face(hm.halfedge_twin(h));
      if (self) {
        if (seam.count({u, v})) to_source = true;
        if (seam.count({v, u})) to_sink = true;
      }
      for (int w : {u, v})
        if (!self && on_other_loop(w)) {
          const int m = vertex_loop[w];
          if (face_piece[f] == a && other_a[m]) to_source = true;
          if (face_piece[f] == b && other_b[m]) to_sink = true;
        }
      if (!self && node[g] < 0 && face_piece[g] == face_piece[f]) (face_piece[f] == a ? to_source : to_sink) = true;
      if (!self && joined[f]) (face_piece[f] == a ? to_source : to_sink) = true;
      if (node[g] < 0 || g < f) continue;
      if (self && (seam.count({u, v}) || seam.count({v, u}))) continue;  // cut open along the loop
      if (open_edges.count({std::min(u, v), std::max(u, v)})) continue;
      const double c = on_other_loop(u) || on_other_loop(v)
                           ? kInfinity
                           : std::max(quantum, quantum * std::round((hm.positions().row(u) - hm.positions().row(v)).norm() / quantum));
      cut.add_arc(node[f], node[g], c, c);
    }
    if (to_source && to_sink) return {};
    if (to_source) cut.add_arc(source, node[f], kInfinity, 0.0);
    if (to_sink) cut.add_arc(node[f], sink, kInfinity, 0.0);
  }
  const double length = cut.solve(source, sink);
  // A loop only a little shorter stays where it is: the level set is smoother than an edge path,
  // and on a symmetric shape many loops tie within rounding.
  const bool cap = !self && (!has_a || !has_b);
  if (!(length < (cap ? kCapGain : kMinGain) * loop_length(d.mesh, loop.vertices))) return {};
  const std::vector<char>& side = cut.source_side();
  // The cut's edges, directed with the source side on the left; one simple loop or nothing.
  std::vector<int> next(hm.num_vertices(), -1);
  int num_edges = 0, start = -1;
  for (int f : faces) {
    if (!side[node[f]]) continue;
    for (int h : hm.face_halfedges(f)) {
      const int g = hm.halfedge_face(hm.halfedge_twin(h));
      if (node[g] < 0 || side[node[g]]) continue;
      const int u = hm.halfedge_source(h), v = hm.halfedge_vertex(h);
      if (self && seam.count({u, v})) continue;
      if (next[u] >= 0) return {};
      next[u] = v;
      ++num_edges;
      if (start < 0 || u < start) start = u;
    }
  }
  if (num_edges < 3) return {};
  std::vector<int> out;
  for (int v = start;;) {
    out.push_back(v);
    v = next[v];
    if (v < 0) return {};
    if (v == start) break;
    if (static_cast<int>(out.size()) > num_edges) return {};
  }
  if (static_cast<int>(out.size()) != num_edges) return {};
  below.clear();
  for (int f : faces) below.push_back({f, side[node[f]]});
  return out;
}

// A level-set loop runs through split edges, so no edge joins two loop vertices off the loop; a
// loop along mesh edges may have such chords (a triangle with three loop vertices, flat in a
// piece's boundary map). Each chord is split at its midpoint; a split face keeps its id for its
// first part and the other parts are appended to its piece.
void split_loop_chords(SolidDecomposition& d) {
  const int n = d.mesh.num_vertices(), m = d.mesh.num_faces();
  std::vector<char> on_loop(n, 0);
  std::set<std::pair<int, int>> loop_edges;
  for (const CutLoop& l : d.loops)
    for (std::size_t i = 0; i < l.vertices.size(); ++i) {
      const int a = l.vertices[i], b = l.vertices[(i + 1) % l.vertices.size()];
      on_loop[a] = 1;
      loop_edges.insert({std::min(a, b), std::max(a, b)});
    }
  mesh::EdgeMidpoints midpoint;
  for (int f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = d.mesh.triangles(f, k), b = d.mesh.triangles(f, (k + 1) % 3);
      const std::pair<int, int> e{std::min(a, b), std::max(a, b)};
      if (on_loop[a] && on_loop[b] && !loop_edges.count(e) && !midpoint.count(e))
        midpoint.emplace(e, n + static_cast<int>(midpoint.size()));
    }
  if (midpoint.empty()) return;
  d.mesh.positions.conservativeResize(n + static_cast<int>(midpoint.size()), 3);
  d.value.resize(n + midpoint.size());
  for (const auto& [e, v] : midpoint) {
    d.mesh.positions.row(v) = 0.5 * (d.mesh.positions.row(e.first) + d.mesh.positions.row(e.second));
    d.value[v] = 0.5 * (d.value[e.first] + d.value[e.second]);
  }
  std::vector<int> face_piece(m, -1);
  for (std::size_t p = 0; p < d.pieces.size(); ++p)
    for (int f : d.pieces[p].faces) face_piece[f] = static_cast<int>(p);
  std::vector<std::array<int, 3>> tris(m);
  for (int f = 0; f < m; ++f) tris[f] = {d.mesh.triangles(f, 0), d.mesh.triangles(f, 1), d.mesh.triangles(f, 2)};
  for (int f = 0; f < m; ++f) {
    const std::vector<std::array<int, 3>> parts = mesh::split_at_midpoints(tris[f], midpoint, n);
    tris[f] = parts[0];
    for (std::size_t i = 1; i < parts.size(); ++i) {
      tris.push_back(parts[i]);
      d.parent_face.push_back(d.parent_face[f]);
      if (face_piece[f] >= 0) d.pieces[face_piece[f]].faces.push_back(static_cast<int>(tris.size()) - 1);
    }
  }
  d.mesh.triangles = mesh::triangles_from(tris);
}

}  // namespace

CutTightening tighten_cut_loops(SolidDecomposition& d, bool caps, int only_loop) {
  CutTightening out;
  if (d.loops.empty()) return out;
  const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(d.mesh, "decomposition");
  std::vector<int> face_piece(hm.num_faces(), -1);
  for (std::size_t p = 0; p < d.pieces.size(); ++p)
    for (int f : d.pieces[p].faces) face_piece[f] = static_cast<int>(p);
  std::vector<int> vertex_loop(hm.num_vertices(), -1);
  for (std::size_t l = 0; l < d.loops.size(); ++l) {
    for (int v : d.loops[l].vertices) vertex_loop[v] = static_cast<int>(l);
    out.length_before += loop_length(d.mesh, d.loops[l].vertices);
  }
  // Capacities are edge lengths rounded to multiples of a power of two near 2^-32 of the size:
  // the flow's sums are then exact, so its ties do not depend on rounding (where the model sits).
  const Eigen::RowVector3d lo = d.mesh.positions.colwise().minCoeff(), hi = d.mesh.positions.colwise().maxCoeff();
  const double quantum = std::ldexp(1.0, std::ilogb(std::max((hi - lo).norm(), 1e-300)) - 32);
  std::vector<char> changed(d.pieces.size(), 0);
  for (std::size_t l = 0; l < d.loops.size(); ++l) {
    if (only_loop >= 0 && static_cast<int>(l) != only_loop) continue;
    CutLoop& loop = d.loops[l];
    // The certificate of the cut as it is, computed once and only where needed (it scans the surface).
    std::optional<DiscEmbedding> before;
    // The cut of a tube closed on itself is the only cut of its one cuboid, whose cross-section it
    // sets (the 4 poly-edges across are its quarters): moved to the tube's thinnest place it would
    // squeeze the whole tube, so it stays unless its disc crosses the surface.
    if (loop.piece[0] == loop.piece[1] && d.pieces[loop.piece[0]].boundary.size() == 2) {
      before = check_loop_disc(d.mesh, loop.vertices);
      if (before->num_intersections == 0) continue;
    }
    // The whole two pieces first; where their shortest separator is several loops (around two
    // boundaries apart), bands of shrinking width around the cut. A tube closed on itself is cut
    // open along its loop: any essential loop of the annulus is a meridian.
    const double length = loop_length(d.mesh, loop.vertices);
    std::vector<double> radii{kInfinity, 0.5 * length, 0.25 * length, 0.125 * length, 0.0625 * length};
    if (loop.piece[0] == loop.piece[1]) radii = {kInfinity};
    // A cap's side holds no other loop: its terminal is the band's rim, since in the whole cap the
    // shortest loop would shrink onto the limb's end. A level set through the thick junction where
    // a limb meets the body runs diagonally (2-3 times the limb's cross-section on armadillo's hips
    // and shoulders); in a band a quarter of its length wide the shortest loop is the
    // cross-section at the junction, where a wider band lets it slide along the limb to its
    // narrowest place (a wrist), shortening the cap and leaving the limb's base to the T-shape.
    const bool cap = d.pieces[loop.piece[0]].boundary.size() == 1 || d.pieces[loop.piece[1]].boundary.size() == 1;
    if (cap && !caps) continue;
    if (cap) radii = {0.25 * length, 0.125 * length, 0.0625 * length};
    std::vector<double> distance;
    std::vector<int> tight;
    std::vector<std::pair<int, char>> below;
    for (double radius : radii) {
      if (!std::isinf(radius) && distance.empty())
        distance = mesh::graph_distances(hm, loop.vertices).distance;
      if (std::isinf(radius)) distance.assign(hm.num_vertices(), 0.0);
      tight = shortest_loop(hm, d, face_piece, vertex_loop, static_cast<int>(l), distance, radius, quantum, below);
      if (std::isinf(radius)) distance.clear();
      if (!tight.empty()) break;
    }
    if (tight.empty()) continue;
    const int a = loop.piece[0], b = loop.piece[1];
    std::vector<int> candidate = face_piece;
    if (a != b) {
      for (const auto& [f, s] : below) candidate[f] = s ? a : b;
      if (!planar_with_loops(hm, candidate, a, static_cast<int>(d.pieces[a].boundary.size())) ||
          !planar_with_loops(hm, candidate, b, static_cast<int>(d.pieces[b].boundary.size())))
        continue;
    }
    const DiscEmbedding after = check_loop_disc(d.mesh, tight);
    if (!before) before = check_loop_disc(d.mesh, loop.vertices);
    if (after.num_outside > 0 || after.num_intersections > before->num_intersections) continue;
    face_piece = std::move(candidate);
    for (int v : loop.vertices) vertex_loop[v] = -1;
    for (int v : tight) vertex_loop[v] = static_cast<int>(l);
    loop.vertices = tight;
    changed[a] = changed[b] = 1;
    ++out.num_tightened;
  }
  for (std::size_t p = 0; p < d.pieces.size(); ++p) {
    if (!changed[p]) continue;
    d.pieces[p].faces.clear();
    for (int f = 0; f < hm.num_faces(); ++f)
      if (face_piece[f] == static_cast<int>(p)) d.pieces[p].faces.push_back(f);
  }
  for (const CutLoop& loop : d.loops) out.length_after += loop_length(d.mesh, loop.vertices);
  if (out.num_tightened > 0) split_loop_chords(d);
  return out;
}

}  // namespace volspline::polycube
