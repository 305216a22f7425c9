// SPDX-License-Identifier: MIT
#include "core/polycube/piece_resplit.h"

#include <algorithm>
#include <array>
#include <limits>
#include <map>

#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/mesh/edge_weights.h"
#include "core/mesh/graph_distance.h"
#include "core/mesh/mesh_lists.h"
#include "core/polycube/interface_disc.h"
#include "core/polycube/level_set_split.h"
#include "core/polycube/morse_function.h"

namespace volspline::polycube {

namespace {

// The merged piece as a mesh of its own: a loop with both sides in it has its vertices twice.
struct MergedPiece {
  mesh::TriangleMesh mesh;
  std::vector<int> surface_vertex;         // per local vertex
  std::vector<int> surface_face;           // per local face
  std::vector<std::vector<int>> boundary;  // per entry: local vertex per loop vertex
};

// A re-split of the merged piece by one pairing of its 4 boundary entries.
struct Candidate {
  mesh::TriangleMesh mesh;
  std::vector<double> value;
  std::vector<int> parent_face;
  std::vector<int> loop;          // d.mesh ids, the u < level side on its left
  std::vector<int> faces[2];      // faces of d.mesh with u < level and u > level
  int zero_pair = 0;              // entries 0 and zero_pair are the u = 0 pair
  int crossings = 0;
  double length = 0.0;
  double level = 0.5;
};

MergedPiece extract_merged(const SolidDecomposition& d, const mesh::HalfedgeMesh& hm, const std::vector<int>& faces,
                           const std::vector<LoopSide>& entries) {
  // Corners of faces left of a two-sided loop (side 0): the fan from v→next counter-clockwise to
  // v→prev. A cut loop runs with its side-0 faces on its left (CutLoop::vertices).
  std::map<int, int> sides;
  for (const LoopSide& e : entries) sides[e.loop] |= 1 << e.side;
  const int nv = hm.num_vertices();
  std::vector<char> two_sided(nv, 0);
  std::vector<char> left_corner(3 * static_cast<std::size_t>(hm.num_faces()), 0);
  for (const auto& [l, mask] : sides) {
    if (mask != 3) continue;
    const std::vector<int>& loop = d.loops[l].vertices;
    const int m = static_cast<int>(loop.size());
    for (int i = 0; i < m; ++i) {
      const int v = loop[i], next = loop[(i + 1) % m], prev = loop[(i + m - 1) % m];
      two_sided[v] = 1;
      int h = mesh::no_id;
      for (int g : hm.vertex_outgoing(v))
        if (hm.halfedge_vertex(g) == next && !hm.halfedge_is_boundary(g)) h = g;
      for (int guard = 0; h != mesh::no_id && hm.halfedge_vertex(h) != prev && guard < 1000; ++guard) {
        left_corner[h] = 1;  // halfedge 3f+k leaves corner k of f
        h = hm.halfedge_twin(hm.halfedge_prev(h));
      }
    }
  }
  MergedPiece out;
  std::map<std::pair<int, int>, int> key_id;
  auto local = [&](int v, int side) {
    const std::pair<int, int> key{v, two_sided[v] ? side : -1};
    auto it = key_id.find(key);
    if (it == key_id.end()) {
      it = key_id.emplace(key, static_cast<int>(out.surface_vertex.size())).first;
      out.surface_vertex.push_back(v);
    }
    return it->second;
  };
  std::vector<std::array<int, 3>> tris;
  for (int f : faces) {
    std::array<int, 3> t;
    for (int k = 0; k < 3; ++k) t[k] = local(d.mesh.triangles(f, k), left_corner[3 * f + k] ? 0 : 1);
    tris.push_back(t);
    out.surface_face.push_back(f);
  }
  for (const LoopSide& e : entries) {
    std::vector<int> ids;
    for (int v : d.loops[e.loop].vertices) ids.push_back(local(v, e.side));
    out.boundary.push_back(std::move(ids));
  }
  out.mesh.positions.resize(static_cast<int>(out.surface_vertex.size()), 3);
  for (std::size_t v = 0; v < out.surface_vertex.size(); ++v)
    out.mesh.positions.row(static_cast<int>(v)) = d.mesh.positions.row(out.surface_vertex[v]);
  out.mesh.triangles = mesh::triangles_from(tris);
  return out;
}

// Splits the sphere with 4 holes made of `faces` (boundary `entries`) by the best meridian over
// its 3 pairings into pieces a (the pair at u = 0) and b, the new cut stored as loop `loop`
// (see resplit_across_loop). On failure `d` is unchanged.
bool split_four_holes(SolidDecomposition& d, int loop, int a, int b, const std::vector<LoopSide>& entries,
                      const std::vector<int>& faces, const ResplitOptions& options, std::string* why) {
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(d.mesh, "decomposition");
  const MergedPiece merged = extract_merged(d, hm, faces, entries);
  const mesh::HalfedgeMesh sub = mesh::HalfedgeMesh::build(merged.mesh, "merged piece");
  const int n = sub.num_vertices();
  std::vector<int> entry_of(n, -1);
  for (std::size_t e = 0; e < entries.size(); ++e)
    for (int v : merged.boundary[e]) entry_of[v] = static_cast<int>(e);
  for (int v = 0; v < n; ++v)
    if (sub.vertex_is_boundary(v) && entry_of[v] < 0)
      return fail("the merged piece has a boundary vertex on none of its cuts (internal error)");

  // One matrix for all pairings: the Dirichlet values change only the right-hand side.
  std::vector<int> unknown(n, -1);
  int num_unknowns = 0;
  for (int v = 0; v < n; ++v)
    if (entry_of[v] < 0) unknown[v] = num_unknowns++;
  const std::vector<double> mvc = mesh::mean_value_weights(sub);
  std::vector<linalg::Triplet> triplets;
  std::vector<std::vector<std::pair<int, double>>> dirichlet(num_unknowns);
  for (int v = 0; v < n; ++v) {
    if (unknown[v] < 0) continue;
    double diagonal = 0.0;
    for (int h : sub.vertex_outgoing(v)) {
      const int u = sub.halfedge_vertex(h);
      // Symmetrized mean-value weights: positive, so the maximum principle holds.
      const double w = 0.5 * (mvc[h] + mvc[sub.halfedge_twin(h)]);
      diagonal += w;
      if (unknown[u] >= 0)
        triplets.push_back({unknown[v], unknown[u], -w});
      else
        dirichlet[unknown[v]].push_back({entry_of[u], w});
    }
    triplets.push_back({unknown[v], unknown[v], diagonal > 0.0 ? diagonal : 1.0});
  }
  linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
  if (num_unknowns > 0) {
    cg.set_tolerance(options.tolerance);
    cg.set_max_iterations(std::max(1000, 4 * num_unknowns));
    cg.compute(linalg::CsrMatrix::from_triplets(num_unknowns, num_unknowns, triplets));
  }
  std::vector<char> frozen(n, 0);
  for (int v = 0; v < n; ++v) frozen[v] = entry_of[v] >= 0;

  const int nv = d.mesh.num_vertices(), nf = d.mesh.num_faces();
  std::vector<char> in_merged(nf, 0);
  for (int f : faces) in_merged[f] = 1;
  // The 3 pairings' solves in one call: they stream the matrix and the factor once per
  // iteration for all 3, each column bit-identical to its lone solve.
  auto entry_values = [](int pair) {
    std::array<double, 4> value{};
    for (int e = 1; e < 4; ++e) value[e] = e == pair ? 0.0 : 1.0;
    return value;
  };
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(num_unknowns, 3);
  for (int pair = 1; pair < 4; ++pair) {
    const std::array<double, 4> entry_value = entry_values(pair);
    for (int i = 0; i < num_unknowns; ++i)
      for (const auto& [e, w] : dirichlet[i]) rhs(i, pair - 1) += w * entry_value[e];
  }
  const Eigen::MatrixXd solution =
      num_unknowns > 0 ? Eigen::MatrixXd(cg.solve(rhs, Eigen::MatrixXd::Constant(num_unknowns, 3, 0.5))) : rhs;
  std::vector<Candidate> accepted;
  std::string rejected;
  for (int pair = 1; pair < 4; ++pair) {
    const std::array<double, 4> entry_value = entry_values(pair);
    const auto x = solution.col(pair - 1);
    std::vector<double> u(n);
    for (int v = 0; v < n; ++v) u[v] = unknown[v] >= 0 ? std::clamp(x(unknown[v]), 0.0, 1.0) : entry_value[entry_of[v]];
    // u has no interior extremum and 2 saddles (−χ of a sphere with 4 holes); its level set is
    // one loop, separating the pairs, only between them: cut midway.
    MorseFunction morse;
    morse.value = u;
    classify_critical_points(sub, morse);
    std::vector<double> saddle;
    for (int v = 0; v < n; ++v)
      if (entry_of[v] < 0 && morse.kind[v] == CriticalKind::Saddle)
        saddle.insert(saddle.end(), morse.multiplicity[v], u[v]);
    std::sort(saddle.begin(), saddle.end());
    const double level = saddle.size() == 2 ? 0.5 * (saddle[0] + saddle[1]) : 0.5;
    const LevelSetSplit split = split_at_level(merged.mesh, u, {}, level, options.snap, frozen);
    const int ns = split.mesh.num_vertices(), ms = split.mesh.num_faces();
    const mesh::HalfedgeMesh sh = mesh::HalfedgeMesh::build(split.mesh, "merged piece");
    std::vector<int> side(ms);
    for (int t = 0; t < ms; ++t) {
      double c = 0.0;
      for (int k = 0; k < 3; ++k) c += split.value[split.mesh.triangles(t, k)];
      side[t] = c / 3.0 < level ? 0 : 1;
    }
    std::vector<int> next(ns, -1);
    bool simple = true;
    int num_edges = 0;
    for (int h = 0; h < 3 * ms; ++h) {
      const int g = sh.halfedge_face(sh.halfedge_twin(h));
      if (side[h / 3] != 0 || g < 0 || side[g] != 1) continue;
      const int s = sh.halfedge_source(h);
      simple = simple && next[s] < 0;
      next[s] = sh.halfedge_vertex(h);
      ++num_edges;
    }
    // Global ids of the split piece's vertices: old ones map back, new ones are appended.
    auto global = [&](int v) { return v < n ? merged.surface_vertex[v] : nv + (v - n); };
    std::vector<int> level_loop;
    if (simple && num_edges >= 3) {
      int start = 0;
      while (next[start] < 0) ++start;
      int v = start;
      do {
        level_loop.push_back(v);
        v = next[v];
      } while (v >= 0 && v != start && static_cast<int>(level_loop.size()) <= num_edges);
      if (v != start || static_cast<int>(level_loop.size()) != num_edges) level_loop.clear();
    }
    const std::string name = "pairing " + std::to_string(pair);
    if (level_loop.empty()) {
      rejected += (rejected.empty() ? "" : "; ") + name + ": the level set of u between its saddles is not one loop (" +
                  (simple ? std::to_string(num_edges) + " edges" : "it touches itself") + ", " +
                  std::to_string(saddle.size()) + " saddles)";
      continue;
    }
    // Both sides of a loop in one new piece need the loop to be a level set of d.value: that is
    // how the pieces' meshes tell its sides apart (gpc_builder).
    bool sides_ok = true;
    for (int s = 0; s < 2 && sides_ok; ++s) {
      std::map<int, int> mask;
      for (int e = 0; e < 4; ++e)
        if ((entry_value[e] == 0.0) == (s == 0)) mask[entries[e].loop] |= 1 << entries[e].side;
      for (const auto& [l, m] : mask)
        if (m == 3)
          for (int v : d.loops[l].vertices) sides_ok = sides_ok && d.value[v] == d.loops[l].level;
    }
    if (!sides_ok) {
      rejected += (rejected.empty() ? "" : "; ") + name + ": a re-split cut would bound one piece on both sides";
      continue;
    }

    Candidate c;
    c.zero_pair = pair;
    c.level = level;
    c.mesh.positions.resize(nv + (ns - n), 3);
    c.mesh.positions.topRows(nv) = d.mesh.positions;
    c.mesh.positions.bottomRows(ns - n) = split.mesh.positions.bottomRows(ns - n);
    c.value = d.value;
    for (int k = 0; k < ns - n; ++k) {
      const auto [ea, eb] = split.new_vertex_edge[k];
      const double t = split.new_vertex_t[k];
      c.value.push_back((1.0 - t) * d.value[global(ea)] + t * d.value[global(eb)]);
    }
    // Faces: a split face keeps its id for its first part, further parts are appended.
    std::vector<std::array<int, 3>> tris(nf);
    c.parent_face = d.parent_face;
    for (int f = 0; f < nf; ++f) tris[f] = {d.mesh.triangles(f, 0), d.mesh.triangles(f, 1), d.mesh.triangles(f, 2)};
    std::vector<char> reused(merged.surface_face.size(), 0);
    for (int t = 0; t < ms; ++t) {
      const int local_parent = split.parent_face[t];
      const int f0 = merged.surface_face[local_parent];
      int f = f0;
      if (reused[local_parent]) {
        f = static_cast<int>(tris.size());
        tris.emplace_back();
        c.parent_face.push_back(d.parent_face[f0]);
      }
      reused[local_parent] = 1;
      for (int k = 0; k < 3; ++k) tris[f][k] = global(split.mesh.triangles(t, k));
      c.faces[side[t]].push_back(f);
    }
    c.mesh.triangles = mesh::triangles_from(tris);
    for (auto& list : c.faces) std::sort(list.begin(), list.end());
    for (int v : level_loop) c.loop.push_back(global(v));
    c.length = loop_length(c.mesh, c.loop);
    const DiscEmbedding check = check_loop_disc(c.mesh, c.loop);
    if (check.num_outside > 0) {
      rejected += (rejected.empty() ? "" : "; ") + name + ": its disc lies outside the solid (winding number " +
                  std::to_string(check.winding[0]) + ")";
      continue;
    }
    c.crossings = check.num_intersections;
    accepted.push_back(std::move(c));
  }
  if (accepted.empty()) return fail("no pairing of the 4 loops gives a meridian: " + rejected);
  const Candidate& best = *std::min_element(accepted.begin(), accepted.end(), [](const Candidate& x, const Candidate& y) {
    if (x.crossings != y.crossings) return x.crossings < y.crossings;
    if (x.length != y.length) return x.length < y.length;
    return x.zero_pair < y.zero_pair;
  });

  d.mesh = best.mesh;
  d.value = best.value;
  d.parent_face = best.parent_face;
  CutLoop& cut = d.loops[loop];
  cut.vertices = best.loop;
  cut.level = best.level;
  const std::array<int, 2> piece{a, b};
  for (int s = 0; s < 2; ++s) {
    SolidPiece& p = d.pieces[piece[s]];
    p.faces = best.faces[s];
    p.boundary.clear();
    p.boundary.push_back({loop, s});
    for (int e = 0; e < 4; ++e)
      if ((e == 0 || e == best.zero_pair) == (s == 0)) {
        p.boundary.push_back(entries[e]);
        d.loops[entries[e].loop].piece[entries[e].side] = piece[s];
      }
    std::sort(p.boundary.begin(), p.boundary.end(),
              [](const LoopSide& x, const LoopSide& y) { return x.loop != y.loop ? x.loop < y.loop : x.side < y.side; });
    p.kind = PieceKind::TShape;
  }
  return true;
}

}  // namespace

bool resplit_across_loop(SolidDecomposition& d, int loop, const ResplitOptions& options, std::string* why) {
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  const int a = d.loops[loop].piece[0], b = d.loops[loop].piece[1];
  if (a == b) return fail("both sides of the cut are piece " + std::to_string(a) + " (a handle cut along itself)");
  std::vector<LoopSide> entries;
  for (int p : {a, b})
    for (const LoopSide& s : d.pieces[p].boundary)
      if (s.loop != loop) entries.push_back(s);
  if (entries.size() != 4)
    return fail("its pieces " + std::to_string(a) + " and " + std::to_string(b) + " have " +
                std::to_string(entries.size()) + " other boundary loops (a re-split needs two T-shapes, 4)");
  std::vector<int> faces = d.pieces[a].faces;
  faces.insert(faces.end(), d.pieces[b].faces.begin(), d.pieces[b].faces.end());
  std::sort(faces.begin(), faces.end());
  return split_four_holes(d, loop, a, b, entries, faces, options, why);
}

bool split_four_holed_piece(SolidDecomposition& d, int piece, const ResplitOptions& options, std::string* why) {
  if (d.pieces[piece].boundary.size() != 4) {
    if (why) *why = "it has " + std::to_string(d.pieces[piece].boundary.size()) + " boundary loops, not 4";
    return false;
  }
  const std::vector<LoopSide> entries = d.pieces[piece].boundary;
  const std::vector<int> faces = d.pieces[piece].faces;
  const int loop = static_cast<int>(d.loops.size()), other = static_cast<int>(d.pieces.size());
  d.loops.emplace_back();
  d.loops.back().piece = {piece, other};
  d.pieces.emplace_back();
  if (split_four_holes(d, loop, piece, other, entries, faces, options, why)) return true;
  d.loops.pop_back();
  d.pieces.pop_back();
  return false;
}

bool replace_handle_cut(SolidDecomposition& d, int loop, std::string* why) {
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  const int p = d.loops[loop].piece[0];
  if (d.loops[loop].piece[1] != p || d.pieces[p].boundary.size() != 2)
    return fail("its sides are not one tube closed on itself");
  const std::vector<LoopSide> entries = {{loop, 0}, {loop, 1}};
  const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(d.mesh, "decomposition");
  const MergedPiece tube = extract_merged(d, hm, d.pieces[p].faces, entries);
  const mesh::HalfedgeMesh sub = mesh::HalfedgeMesh::build(tube.mesh, "tube");
  const int n = sub.num_vertices(), m = static_cast<int>(tube.boundary[0].size());
  std::vector<char> on_boundary(n, 0);
  for (const auto& b : tube.boundary)
    for (int v : b) on_boundary[v] = 1;
  std::vector<double> length(sub.num_edges());
  for (int e = 0; e < sub.num_edges(); ++e) {
    const auto [a, b] = sub.edge_vertices(e);
    length[e] = (tube.mesh.positions.row(a) - tube.mesh.positions.row(b)).norm();
  }
  // Shortest crossing at every loop vertex, the path kept off the loop between its ends.
  struct Crossing {
    double length;
    int at;
    std::vector<int> path;  // tube vertices, from the side-0 copy to the side-1 copy
  };
  std::vector<Crossing> crossings;
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < m; ++i) {
    const int from = tube.boundary[0][i], to = tube.boundary[1][i];
    std::vector<double> blocked = length;
    for (int e = 0; e < sub.num_edges(); ++e) {
      const auto [a, b] = sub.edge_vertices(e);
      for (int v : {a, b})
        if (on_boundary[v] && v != from && v != to) blocked[e] = inf;
    }
    const mesh::GraphDistances dist = mesh::graph_distances(sub, {from}, blocked);
    if (!(dist.distance[to] < inf)) continue;
    crossings.push_back({dist.distance[to], i, mesh::graph_path(dist, to)});
  }
  std::sort(crossings.begin(), crossings.end(),
            [](const Crossing& x, const Crossing& y) { return x.length != y.length ? x.length < y.length : x.at < y.at; });
  struct Accepted {
    int crossings;
    double length;
    std::vector<int> loop;
    std::vector<double> value;
  };
  std::vector<Accepted> accepted;
  std::string rejected;
  const int tries = std::min<int>(8, static_cast<int>(crossings.size()));
  for (int c = 0; c < tries; ++c) {
    const std::vector<int>& path = crossings[c].path;
    std::vector<int> cycle;
    for (std::size_t k = 0; k + 1 < path.size(); ++k) cycle.push_back(tube.surface_vertex[path[k]]);
    if (cycle.size() < 3) continue;
    const DiscEmbedding check = check_loop_disc(d.mesh, cycle);
    if (check.num_outside > 0) {
      rejected = "the shortest crossings' discs lie outside the solid (winding number " +
                 std::to_string(check.winding[0]) + ")";
      continue;
    }
    // The value: harmonic on the tube cut open along the new loop, 0 left of it, 1 right.
    SolidDecomposition trial = d;
    trial.loops[loop].vertices = cycle;
    const MergedPiece open = extract_merged(trial, hm, d.pieces[p].faces, entries);
    const mesh::HalfedgeMesh oh = mesh::HalfedgeMesh::build(open.mesh, "tube");
    const int no = oh.num_vertices();
    std::vector<double> fixed(no, -1.0);
    for (int side = 0; side < 2; ++side)
      for (int v : open.boundary[side]) fixed[v] = side;
    std::vector<int> unknown(no, -1);
    int num_unknowns = 0;
    for (int v = 0; v < no; ++v)
      if (fixed[v] < 0.0) unknown[v] = num_unknowns++;
    const std::vector<double> mvc = mesh::mean_value_weights(oh);
    std::vector<linalg::Triplet> triplets;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(num_unknowns);
    for (int v = 0; v < no; ++v) {
      if (unknown[v] < 0) continue;
      double diagonal = 0.0;
      for (int h : oh.vertex_outgoing(v)) {
        const int u = oh.halfedge_vertex(h);
        const double w = 0.5 * (mvc[h] + mvc[oh.halfedge_twin(h)]);
        diagonal += w;
        if (unknown[u] >= 0)
          triplets.push_back({unknown[v], unknown[u], -w});
        else
          rhs(unknown[v]) += w * fixed[u];
      }
      triplets.push_back({unknown[v], unknown[v], diagonal > 0.0 ? diagonal : 1.0});
    }
    if (num_unknowns == 0) continue;
    linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
    cg.set_tolerance(1e-12);
    cg.set_max_iterations(std::max(1000, 4 * num_unknowns));
    cg.compute(linalg::CsrMatrix::from_triplets(num_unknowns, num_unknowns, triplets));
    const Eigen::VectorXd x = cg.solve(rhs, Eigen::VectorXd::Constant(num_unknowns, 0.5));
    std::vector<double> value = d.value;
    for (int v = 0; v < no; ++v)
      value[open.surface_vertex[v]] = unknown[v] >= 0 ? std::clamp(x(unknown[v]), 0.0, 1.0) : 0.5;
    // Every face touching the loop must fall on its side by value (as gpc_builder tells them).
    bool consistent = true;
    for (std::size_t t = 0; t < open.surface_face.size() && consistent; ++t) {
      int side = -1;
      double centroid = 0.0;
      for (int k = 0; k < 3; ++k) {
        const int v = open.mesh.triangles(static_cast<int>(t), k);
        if (fixed[v] >= 0.0) side = static_cast<int>(fixed[v]);
        centroid += value[open.surface_vertex[v]] / 3.0;
      }
      if (side >= 0) consistent = (centroid < 0.5 ? 0 : 1) == side;
    }
    if (!consistent) {
      rejected = "a face at a crossing's loop cannot be told apart by value";
      continue;
    }
    accepted.push_back({check.num_intersections, crossings[c].length, cycle, std::move(value)});
  }
  if (accepted.empty())
    return fail(crossings.empty() ? "no path crosses the tube" : "no crossing qualifies: " + rejected);
  const Accepted& best = *std::min_element(accepted.begin(), accepted.end(), [](const Accepted& x, const Accepted& y) {
    return x.crossings != y.crossings ? x.crossings < y.crossings : x.length < y.length;
  });
  d.loops[loop].vertices = best.loop;
  d.loops[loop].level = 0.5;
  d.value = best.value;
  return true;
}

}  // namespace volspline::polycube
