// SPDX-License-Identifier: MIT
#include "core/polycube/t_shape_layout.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <map>
#include <queue>
#include <set>

#include "core/mesh/graph_distance.h"
#include "core/mesh/mesh_geometry.h"
#include "core/polycube/disc_chords.h"
#include "core/polycube/surface_paths.h"

namespace volspline::polycube {

namespace {

// Edge lengths that make paths keep off the vertices next to the used ones (×4 for an edge that
// touches such a vertex), so that cut paths leave room between them for the later paths. Kept
// up to date as paths are added: each costs its own neighbourhood, not a pass over the mesh.
class RepelledLengths {
 public:
  RepelledLengths(const mesh::HalfedgeMesh& mesh, const std::vector<double>& length)
      : mesh_(mesh), length_(length), out_(length), near_(mesh.num_vertices(), 0) {}
  const std::vector<double>& lengths() const { return out_; }
  // Marks the vertices of `path` used: the edges at their neighbours are repelled.
  void add(const std::vector<int>& path) {
    for (int v : path)
      for (int u : mesh_.vertex_neighbors(v)) {
        if (near_[u]) continue;
        near_[u] = 1;
        for (int h : mesh_.vertex_outgoing(u)) {
          const int e = mesh_.halfedge_edge(h);
          out_[e] = length_[e] * 4.0;
        }
      }
  }

 private:
  const mesh::HalfedgeMesh& mesh_;
  const std::vector<double>& length_;
  std::vector<double> out_;
  std::vector<char> near_;
};

std::vector<int> reversed(std::vector<int> p) {
  std::reverse(p.begin(), p.end());
  return p;
}

// Path along a cycle from a to b (both on it) that contains none of `avoid`.
std::vector<int> cycle_segment(const std::vector<int>& cycle, int a, int b, const std::vector<int>& avoid) {
  const int n = static_cast<int>(cycle.size());
  const int ia = static_cast<int>(std::find(cycle.begin(), cycle.end(), a) - cycle.begin());
  for (int dir : {1, -1}) {
    std::vector<int> path;
    bool ok = true;
    for (int i = ia;; i = ((i + dir) % n + n) % n) {
      path.push_back(cycle[i]);
      if (cycle[i] == b) break;
      if (i != ia && std::find(avoid.begin(), avoid.end(), cycle[i]) != avoid.end()) {
        ok = false;
        break;
      }
      if (static_cast<int>(path.size()) > n) {
        ok = false;
        break;
      }
    }
    if (ok) return path;
  }
  return {};
}

double path_length(const mesh::HalfedgeMesh& m, const std::vector<int>& p) {
  double total = 0.0;
  for (std::size_t i = 1; i < p.size(); ++i) total += (m.vertex_position(p[i]) - m.vertex_position(p[i - 1])).norm();
  return total;
}

// Concatenates paths that share end points into one vertex cycle (first vertex not repeated).
std::vector<int> join_cycle(const std::vector<std::vector<int>>& parts) {
  std::vector<int> cycle;
  for (const auto& p : parts)
    for (std::size_t i = 0; i + 1 < p.size(); ++i) cycle.push_back(p[i]);
  return cycle;
}

struct Seams {
  // seam[i][j] for the loop pair (i, j), i < j: two paths, each from a corner of i to one of j.
  std::map<std::pair<int, int>, std::array<std::vector<int>, 2>> seam;
  double length = 0.0;
  std::vector<int> region;  // per face
  std::array<int, 2> hexagon{-1, -1};
  std::map<std::pair<int, int>, int> rim;  // region of each pair's strip
};

}  // namespace

bool lay_out_t_shape(mesh::TriangleMesh& pants_mesh, std::vector<int>& face_origin, std::vector<double>& vertex_value,
                     const std::array<std::vector<int>, 3>& loops, const std::array<bool, 3>& piece_forward,
                     const std::array<std::array<int, 4>, 3>& corners, const std::vector<int>& vertex_identity,
                     TShapeLayout& out, std::string* why, const TShapeLayoutOptions& options) {
  assert(options.concave_corner_height > 0.0 && options.concave_corner_height <= 1.0);
  const mesh::HalfedgeMesh pants = mesh::HalfedgeMesh::build(pants_mesh, "T-shape");
  const int n = pants.num_vertices();
  const std::vector<double> length = mesh::edge_lengths(pants);
  // Corners of each loop in the pants's halfedge direction along it.
  std::array<std::array<int, 4>, 3> p;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 4; ++i) p[k][i] = loops[k][corners[k][piece_forward[k] ? i : (4 - i) % 4]];
  std::vector<char> on_loop(n, 0);
  for (const auto& l : loops)
    for (int v : l) on_loop[v] = 1;
  // The graph distance between two corners, nothing blocked or repelled: no seam between them
  // is shorter (path_length sums the same edge lengths along the path).
  std::map<int, std::vector<double>> distance_from;
  auto seam_lower_bound = [&](int a, int b) {
    auto known = distance_from.find(a);
    if (known == distance_from.end()) known = distance_from.emplace(a, mesh::graph_distances(pants, {a}, length).distance).first;
    return known->second[b];
  };

  // Two loops that are the two sides of one cut (the arms of a handle) have their seams join
  // each corner to itself: the handle's cuboids then close without a twist.
  auto same = [&](int a, int b) { return !vertex_identity.empty() && vertex_identity[a] == vertex_identity[b]; };
  std::array<std::array<bool, 3>, 3> twins{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) twins[i][j] = i != j && same(loops[i][0], loops[j][0]);
  // Seams for every choice of rim arcs; the valid one with the shortest seams wins, untwisted
  // ones first.
  Seams best;
  best.length = std::numeric_limits<double>::infinity();
  std::map<std::vector<int>, std::vector<int>> searched;  // seam path by the ends of its trial's seams up to it
  std::string reasons;
  for (int trial = 0; trial < 128 && !(trial == 64 && best.hexagon[0] >= 0); ++trial) {
    const int pass = trial / 64, combo = trial % 64;  // pass 0: untwisted only
    // arc[k][o]: the rim arc of loop k toward loop o, as (first, second) in piece direction.
    std::array<std::map<int, std::array<int, 2>>, 3> arc;
    for (int k = 0; k < 3; ++k) {
      const int r = (combo >> (2 * k)) & 1, a = (combo >> (2 * k + 1)) & 1;
      const std::array<int, 2> arc0 = {p[k][r], p[k][r + 1]};
      const std::array<int, 2> arc1 = {p[k][r + 2], p[k][(r + 3) % 4]};
      const int o1 = (k + 1) % 3, o2 = (k + 2) % 3;
      arc[k][o1] = a == 0 ? arc0 : arc1;
      arc[k][o2] = a == 0 ? arc1 : arc0;
    }
    bool twisted = false;
    for (const auto& [i, j] : {std::make_pair(0, 1), std::make_pair(0, 2), std::make_pair(1, 2)})
      if (twins[i][j]) {
        const auto ai = arc[i][j], aj = arc[j][i];
        twisted = twisted || !same(ai[1], aj[0]) || !same(ai[0], aj[1]);
      }
    // Pass 1 runs only if pass 0 found no valid seams, so its untwisted trials would fail again.
    if (twisted == (pass == 0)) continue;
    // The 6 seams' ends: a strip's boundary runs along i from ai[0] to ai[1], then to j, so pair
    // (i, j) has seams ai[1] → aj[0] and aj[1] → ai[0].
    const std::array<std::pair<int, int>, 3> pairs = {std::make_pair(0, 1), std::make_pair(0, 2), std::make_pair(1, 2)};
    std::array<std::array<int, 2>, 6> seam_ends;
    for (int m = 0; m < 3; ++m) {
      const auto ai = arc[pairs[m].first][pairs[m].second], aj = arc[pairs[m].second][pairs[m].first];
      seam_ends[2 * m] = {ai[1], aj[0]};
      seam_ends[2 * m + 1] = {ai[0], aj[1]};
    }
    // A trial whose seams so far plus the lower bounds of the rest reach the best length cannot
    // win: it is dropped before its searches (the margin covers the rounding of the sums).
    std::array<double, 7> chords_after{};
    for (int m = 5; m >= 0; --m)
      chords_after[m] = chords_after[m + 1] + seam_lower_bound(seam_ends[m][0], seam_ends[m][1]);
    if (chords_after[0] * (1.0 - 1e-12) >= best.length) continue;
    Seams s;
    std::vector<int> prefix;  // the ends of the seams searched so far in this trial
    std::vector<char> blocked = on_loop;
    RepelledLengths repelled(pants, length);
    std::vector<char> cut(pants.num_edges(), 0);
    bool ok = true;
    for (int m = 0; m < 3 && ok; ++m) {
      const auto [i, j] = pairs[m];
      for (int q = 0; q < 2 && ok; ++q) {
        const std::array<int, 2>& ends = seam_ends[2 * m + q];
        if ((s.length + chords_after[2 * m + q]) * (1.0 - 1e-12) >= best.length) {
          ok = false;
          break;
        }
        // The blocked vertices and repelled lengths a search sees follow from the ends of the
        // seams before it, so trials that share those ends share its path.
        prefix.push_back(ends[0]);
        prefix.push_back(ends[1]);
        auto known = searched.find(prefix);
        if (known == searched.end())
          known = searched.emplace(prefix, restricted_path(pants, repelled.lengths(), ends[0], ends[1], blocked, nullptr))
                      .first;
        std::vector<int> path = known->second;
        if (path.size() < 3) {
          ok = false;
          break;
        }
        for (int v : path) blocked[v] = 1;
        repelled.add(path);
        mark_path_edges(pants, path, cut);
        s.length += path_length(pants, path);
        s.seam[{i, j}][q] = std::move(path);
        // Seam lengths are positive: a trial already as long as the best cannot win.
        ok = s.length < best.length;
      }
    }
    if (!ok || !(s.length < best.length)) continue;
    // Regions: 2 hexagons touching all 3 loops, 3 strips touching 2.
    const int count = face_components(pants, cut, s.region);
    if (count != 5) continue;
    std::vector<int> touches(count, 0);
    for (int k = 0; k < 3; ++k)
      for (int v : loops[k])
        for (int f : pants.vertex_faces(v)) touches[s.region[f]] |= 1 << k;
    int hexagons = 0;
    bool valid = true;
    for (int r = 0; r < count; ++r) {
      const int bits = touches[r];
      if (bits == 7) {
        if (hexagons < 2) s.hexagon[hexagons] = r;
        ++hexagons;
      } else if (bits == 3 || bits == 5 || bits == 6) {
        const int i = bits == 6 ? 1 : 0, j = bits == 3 ? 1 : 2;
        if (s.rim.count({i, j})) valid = false;
        s.rim[{i, j}] = r;
      } else {
        valid = false;
      }
    }
    if (!valid || hexagons != 2 || s.rim.size() != 3) continue;
    best = std::move(s);
  }
  if (best.hexagon[0] < 0) {
    if (why) *why = "no 6 disjoint seams cut the pants into 2 hexagons and 3 strips";
    return false;
  }

  // The top rim is the longest; its loops are arms 0 and 1, the third loop the stem (arm 2).
  std::pair<int, int> top{0, 1};
  double top_length = -1.0;
  for (const auto& [pair, paths] : best.seam) {
    const double l = path_length(pants, paths[0]) + path_length(pants, paths[1]);
    if (l > top_length) {
      top_length = l;
      top = pair;
    }
  }
  const int l2 = 3 - top.first - top.second;
  auto seam_between = [&](int a, int b, int hexagon) {
    // The seam of pair (a, b) bordering `hexagon`, oriented from loop a to loop b.
    const auto& paths = best.seam.at({std::min(a, b), std::max(a, b)});
    for (const auto& path : paths) {
      const int e = edge_between(pants, path[0], path[1]);
      const int h = pants.edge_halfedge(e);
      const int f = pants.halfedge_face(h), g = pants.halfedge_face(pants.halfedge_twin(h));
      if ((f >= 0 && best.region[f] == hexagon) || (g >= 0 && best.region[g] == hexagon))
        return a < b ? path : reversed(path);
    }
    return std::vector<int>{};
  };
  // Index of the interior vertex of a path nearest to a fraction of its arc length.
  auto midpoint = [&](const std::vector<int>& path, double fraction) {
    std::vector<double> arc(path.size(), 0.0);
    for (std::size_t i = 1; i < path.size(); ++i)
      arc[i] = arc[i - 1] + (pants.vertex_position(path[i]) - pants.vertex_position(path[i - 1])).norm();
    std::size_t best_i = 1;
    for (std::size_t i = 1; i + 1 < path.size(); ++i)
      if (std::abs(arc[i] - fraction * arc.back()) < std::abs(arc[best_i] - fraction * arc.back())) best_i = i;
    return static_cast<int>(best_i);
  };

  std::string last_reason;
  // Mirror images of the centre (front and back swapped, or the two arms) are tried until one is
  // right-handed and its paths exist.
  for (int attempt = 0; attempt < 4; ++attempt) {
    const int flip = attempt & 1;
    const int l0 = (attempt >> 1) ? top.second : top.first, l1 = (attempt >> 1) ? top.first : top.second;
    out.arm_loop = {l0, l1, l2};
    const int hf = best.hexagon[flip], hb = best.hexagon[1 - flip];
    const std::vector<int> sF01 = seam_between(l0, l1, hf), sB01 = seam_between(l0, l1, hb);
    const std::vector<int> sF02 = seam_between(l0, l2, hf), sB02 = seam_between(l0, l2, hb);
    const std::vector<int> sF12 = seam_between(l1, l2, hf), sB12 = seam_between(l1, l2, hb);
    if (sF01.empty() || sB01.empty() || sF02.empty() || sB02.empty() || sF12.empty() || sB12.empty()) {
      last_reason += std::string(last_reason.empty() ? "" : "; ") + "a seam borders no hexagon";
      continue;
    }
    // The centre sits at the junction, where the arms part: its concave corners are the side
    // seams' points at options.concave_corner_height times the crotch's height (the top seams'
    // lowest point in distance from the stem loop), its top corners the top seam's points
    // nearest to them on either side of the crotch (a compact centre also when the arms are
    // long, as in a handle's ring).
    const mesh::GraphDistances from_stem = mesh::graph_distances(pants, loops[l2]);
    const std::vector<double>& height = from_stem.distance;
    auto lowest = [&](const std::vector<int>& seam) {
      int best_i = 1;
      for (int i = 1; i + 1 < static_cast<int>(seam.size()); ++i)
        if (height[seam[i]] < height[seam[best_i]]) best_i = i;
      return best_i;
    };
    auto at_height = [&](const std::vector<int>& seam, double h) {
      // Side seams run from an arm loop to the stem loop; the point nearest height h, kept off
      // the seam's ends (15 % of its vertices).
      const int n_seam = static_cast<int>(seam.size());
      const int lo = std::max(1, static_cast<int>(0.15 * (n_seam - 1))), hi = std::min(n_seam - 2, static_cast<int>(0.85 * (n_seam - 1)));
      int best_i = std::clamp(midpoint(seam, 0.5), lo, std::max(lo, hi));
      for (int i = lo; i <= hi; ++i)
        if (std::abs(height[seam[i]] - h) < std::abs(height[seam[best_i]] - h)) best_i = i;
      return seam[best_i];
    };
    auto nearest_on = [&](const std::vector<int>& seam, int from, int to, int v) {
      // The vertex of seam[from..to) nearest to vertex v.
      int best_i = from;
      for (int i = from; i < to; ++i)
        if ((pants.vertex_position(seam[i]) - pants.vertex_position(v)).squaredNorm() <
            (pants.vertex_position(seam[best_i]) - pants.vertex_position(v)).squaredNorm())
          best_i = i;
      return best_i;
    };
    const int crotch_f = lowest(sF01), crotch_b = lowest(sB01);
    const double concave_height =
        options.concave_corner_height * std::min(height[sF01[crotch_f]], height[sB01[crotch_b]]);
    // sF02 and sF12 run from the arm loops to the stem loop.
    const int p02 = at_height(sF02, concave_height), p12 = at_height(sF12, concave_height);
    const int p02b = at_height(sB02, concave_height), p12b = at_height(sB12, concave_height);
    auto top_corners = [&](const std::vector<int>& seam, int crotch_i, int left, int right) {
      const int n_seam = static_cast<int>(seam.size());
      int a = nearest_on(seam, 1, std::max(2, crotch_i), left);
      int b = nearest_on(seam, std::min(crotch_i + 1, n_seam - 2), n_seam - 1, right);
      if (a >= b) {
        a = midpoint(seam, 1.0 / 3.0);
        b = midpoint(seam, 2.0 / 3.0);
      }
      return std::array<int, 2>{seam[a], seam[b]};
    };
    const auto qf = top_corners(sF01, crotch_f, p02, p12), qb = top_corners(sB01, crotch_b, p02b, p12b);
    const int q01a = qf[0], q01b = qf[1], r01a = qb[0], r01b = qb[1];
    if (q01a == q01b || r01a == r01b) {
      if (why) *why = "a top seam has too few vertices for the centre's two top corners";
      return false;
    }
    // The centre's 10 inner edges: straight chords of the hexagons and rims (disc_chords.h), so
    // they are disjoint by construction. Each try works on a copy of the pants.
    mesh::TriangleMesh cut_mesh = pants_mesh;
    std::vector<int> cut_region = best.region;
    std::vector<int> cut_origin = face_origin;
    std::vector<double> cut_value = vertex_value;
    auto ends_of = [](std::initializer_list<const std::vector<int>*> seams) {
      std::vector<int> c;
      for (const auto* s : seams) {
        c.push_back(s->front());
        c.push_back(s->back());
      }
      return c;
    };
    auto chords_in = [&](int region, const std::vector<int>& corners,
                         const std::vector<std::array<int, 2>>& chords, std::vector<std::vector<int>>& paths) {
      std::vector<int> faces;
      for (int f = 0; f < cut_mesh.num_faces(); ++f)
        if (cut_region[f] == region) faces.push_back(f);
      DiscChords dc;
      std::string reason;
      if (!cut_disc_chords(cut_mesh, faces, corners, chords, dc, &reason)) {
        last_reason += std::string(last_reason.empty() ? "" : "; ") + "region " + std::to_string(region) + ": " + reason;
        return false;
      }
      for (std::size_t f = cut_region.size(); f < dc.face_origin.size(); ++f) {
        cut_region.push_back(cut_region[dc.face_origin[f]]);
        cut_origin.push_back(cut_origin[dc.face_origin[f]]);
      }
      interpolate_added_vertices(dc, cut_value);
      paths = std::move(dc.paths);
      return true;
    };
    const int rim_top = best.rim.at({std::min(l0, l1), std::max(l0, l1)});
    const int rim02 = best.rim.at({std::min(l0, l2), std::max(l0, l2)});
    const int rim12 = best.rim.at({std::min(l1, l2), std::max(l1, l2)});
    std::vector<std::vector<int>> front, back, top_rim, rim0, rim1;
    if (!chords_in(hf, ends_of({&sF01, &sF02, &sF12}), {{{p02, q01a}}, {{p12, q01b}}, {{p02, p12}}}, front) ||
        !chords_in(hb, ends_of({&sB01, &sB02, &sB12}), {{{p02b, r01a}}, {{p12b, r01b}}, {{p02b, p12b}}}, back) ||
        !chords_in(rim_top, ends_of({&sF01, &sB01}), {{{q01a, r01a}}, {{q01b, r01b}}}, top_rim) ||
        !chords_in(rim02, ends_of({&sF02, &sB02}), {{{p02, p02b}}}, rim0) ||
        !chords_in(rim12, ends_of({&sF12, &sB12}), {{{p12, p12b}}}, rim1))
      continue;
    const std::vector<int> &leftF = front[0], &rightF = front[1], &bottomF = front[2];
    const std::vector<int> &leftB = back[0], &rightB = back[1], &bottomB = back[2];
    const std::vector<int> &crossA = top_rim[0], &crossB = top_rim[1], &e0 = rim0[0], &e1 = rim1[0];
    const mesh::HalfedgeMesh cut_pants = mesh::HalfedgeMesh::build(cut_mesh, "T-shape");
    auto index_in = [](const std::vector<int>& path, int v) {
      return static_cast<int>(std::find(path.begin(), path.end(), v) - path.begin());
    };
    // The segments of the top seams between the centre's corners.
    auto sub = [&](const std::vector<int>& path, int a, int b) {
      const int ia = index_in(path, a), ib = index_in(path, b);
      return std::vector<int>(path.begin() + ia, path.begin() + ib + 1);
    };
    const std::vector<int> topF = sub(sF01, q01a, q01b), topB = sub(sB01, r01a, r01b);
    // Inner loops: J0 (arm 0 | centre), J1 (arm 1 | centre), J2 (stem | centre).
    const std::vector<int> j0 = join_cycle({reversed(leftF), e0, leftB, reversed(crossA)});
    const std::vector<int> j1 = join_cycle({reversed(rightF), e1, rightB, reversed(crossB)});
    const std::vector<int> j2 = join_cycle({bottomF, e1, reversed(bottomB), reversed(e0)});
    std::vector<char> cut(cut_pants.num_edges(), 0);
    for (const auto* path : {&leftF, &e0, &leftB, &crossA, &rightF, &e1, &rightB, &crossB, &bottomF, &bottomB})
      mark_path_edges(cut_pants, *path, cut);
    std::vector<int> region;
    if (face_components(cut_pants, cut, region) != 4) {
      last_reason += std::string(last_reason.empty() ? "" : "; ") + "the inner loops do not cut the pants into 4 parts";
      continue;
    }
    std::array<int, 4> part{-1, -1, -1, -1};  // region of the centre and of each arm
    std::vector<int> touch(4, 0);
    for (int k = 0; k < 3; ++k)
      for (int v : loops[k])
        for (int f : cut_pants.vertex_faces(v)) touch[region[f]] |= 1 << k;
    for (int r = 0; r < 4; ++r) {
      if (touch[r] == 0) part[0] = r;
      for (int a = 0; a < 3; ++a)
        if (touch[r] == (1 << out.arm_loop[a])) part[1 + a] = r;
    }
    if (std::find(part.begin(), part.end(), -1) != part.end()) {
      last_reason += std::string(last_reason.empty() ? "" : "; ") + "the inner loops do not separate the arms";
      continue;
    }
    // Orientation: the centre's front face (y = 0) runs 0 → 1 along bottomF in its halfedge
    // direction (cube face 2 lists its corners clockwise seen from outside).
    {
      const int e = edge_between(cut_pants, bottomF[0], bottomF[1]);
      const int h = cut_pants.edge_halfedge(e);
      const int forward = cut_pants.halfedge_source(h) == bottomF[0] ? h : cut_pants.halfedge_twin(h);
      const int f = cut_pants.halfedge_face(forward);
      if (f < 0 || region[f] != part[0]) {
        last_reason += std::string(last_reason.empty() ? "" : "; ") + "mirrored";
        continue;
      }
    }
    for (int c = 0; c < 4; ++c) out.cuboids[c] = TShapeCuboid{};
    for (int f = 0; f < cut_pants.num_faces(); ++f)
      for (int c = 0; c < 4; ++c)
        if (region[f] == part[c]) out.cuboids[c].faces.push_back(f);
    // A closing disc's cycle runs against the cuboid's own halfedges along the loop.
    auto closing = [&](const std::vector<int>& cycle, int c) {
      for (std::size_t i = 0; i < cycle.size(); ++i) {
        const int a = cycle[i], b = cycle[(i + 1) % cycle.size()];
        for (int h : cut_pants.vertex_outgoing(a))
          if (cut_pants.halfedge_vertex(h) == b) {
            const int f = cut_pants.halfedge_face(h);
            if (f >= 0 && region[f] == part[c]) return reversed(cycle);
            const int g = cut_pants.halfedge_face(cut_pants.halfedge_twin(h));
            if (g >= 0 && region[g] == part[c]) return cycle;
          }
      }
      return cycle;
    };
    // Centre: corner bits (x: arm 0 → arm 1, y: front → back, z: stem → top).
    TShapeCuboid& centre = out.cuboids[0];
    centre.corners = {p02, p12, p02b, p12b, q01a, q01b, r01a, r01b};
    auto set_edge = [](TShapeCuboid& c, int a, int b, std::vector<int> path) {
      const int e = cube_edge_between(a, b);
      if (cube_edge_corners(e)[0] != a) std::reverse(path.begin(), path.end());
      c.poly_edges[e] = std::move(path);
    };
    set_edge(centre, 0, 1, bottomF);
    set_edge(centre, 2, 3, bottomB);
    set_edge(centre, 4, 5, topF);
    set_edge(centre, 6, 7, topB);
    set_edge(centre, 0, 2, e0);
    set_edge(centre, 1, 3, e1);
    set_edge(centre, 4, 6, crossA);
    set_edge(centre, 5, 7, crossB);
    set_edge(centre, 0, 4, leftF);
    set_edge(centre, 1, 5, rightF);
    set_edge(centre, 2, 6, leftB);
    set_edge(centre, 3, 7, rightB);
    centre.face_role = {3, 4, -1, -1, 5, -1};
    centre.discs = {closing(j0, 0), closing(j1, 0), closing(j2, 0)};
    // Arms: face 4 on the boundary loop (corners in the arm's halfedge direction, cube order
    // 0, 1, 3, 2), face 5 on the inner loop, reached along the seams.
    const std::array<std::vector<int>, 3> inner = {j0, j1, j2};
    const std::array<std::array<int, 4>, 3> inner_corners = {
        {{q01a, p02, p02b, r01a}, {q01b, p12, p12b, r01b}, {p02, p12, p12b, p02b}}};
    const std::array<std::vector<int>, 6> seams = {sF01, sB01, sF02, sB02, sF12, sB12};
    for (int a = 0; a < 3; ++a) {
      TShapeCuboid& arm = out.cuboids[1 + a];
      const int k = out.arm_loop[a];
      const std::array<int, 4> bottom = {0, 1, 3, 2};
      for (int i = 0; i < 4; ++i) {
        const int corner = p[k][i];
        arm.corners[bottom[i]] = corner;
        // The seam leaving this corner, cut at the inner loop.
        std::vector<int> band;
        for (const auto& seam : seams) {
          std::vector<int> s = seam.front() == corner ? seam : (seam.back() == corner ? reversed(seam) : std::vector<int>{});
          if (s.empty()) continue;
          for (std::size_t t = 0; t < s.size(); ++t) {
            band.push_back(s[t]);
            if (std::find(inner_corners[a].begin(), inner_corners[a].end(), s[t]) != inner_corners[a].end() && t > 0) break;
          }
          break;
        }
        if (band.size() < 2 ||
            std::find(inner_corners[a].begin(), inner_corners[a].end(), band.back()) == inner_corners[a].end()) {
          if (why) *why = "a seam of arm " + std::to_string(a) + " does not reach its inner loop";
          return false;
        }
        arm.corners[bottom[i] + 4] = band.back();
        set_edge(arm, bottom[i], bottom[i] + 4, band);
      }
      for (int i = 0; i < 4; ++i) {
        const int ca = bottom[i], cb = bottom[(i + 1) % 4];
        // Bottom: along the boundary loop; top: along the inner loop.
        std::vector<int> avoid_bottom, avoid_top;
        for (int q = 0; q < 4; ++q) {
          avoid_bottom.push_back(arm.corners[bottom[q]]);
          avoid_top.push_back(arm.corners[bottom[q] + 4]);
        }
        set_edge(arm, ca, cb, cycle_segment(loops[k], arm.corners[ca], arm.corners[cb], avoid_bottom));
        set_edge(arm, ca + 4, cb + 4, cycle_segment(inner[a], arm.corners[ca + 4], arm.corners[cb + 4], avoid_top));
      }
      arm.face_role = {-1, -1, -1, -1, k, 3 + a};
      arm.discs = {closing(loops[k], 1 + a), closing(inner[a], 1 + a)};
    }
    out.concave_edges = {{{p02, p02b}, {p12, p12b}}};
    pants_mesh = std::move(cut_mesh);
    face_origin = std::move(cut_origin);
    vertex_value = std::move(cut_value);
    return true;
  }
  if (why) *why = last_reason;
  return false;
}

}  // namespace volspline::polycube
