// SPDX-License-Identifier: MIT
#include "core/polycube/disc_chords.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/mesh/edge_weights.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/polycube/level_set_split.h"

namespace volspline::polycube {

namespace {

constexpr double pi = 3.14159265358979323846;

bool fail(std::string* why, const std::string& reason) {
  if (why) *why = reason;
  return false;
}

// Floater map of a disc onto the convex polygon of its corners on the unit circle.
bool map_disc(const mesh::HalfedgeMesh& disc, const std::vector<int>& corners, std::vector<Eigen::Vector2d>& uv,
              std::string* why) {
  const int n = disc.num_vertices();
  std::vector<int> boundary_next(n, -1);
  int start = -1, boundary_count = 0;
  for (int h = 3 * disc.num_faces(); h < disc.num_halfedges(); ++h) {
    const int s = disc.halfedge_source(h);
    if (boundary_next[s] >= 0) return fail(why, "the region's boundary touches itself");
    boundary_next[s] = disc.halfedge_vertex(h);
    ++boundary_count;
    if (start < 0) start = s;
  }
  if (start < 0) return fail(why, "the region has no boundary");
  std::vector<int> cycle;
  for (int v = start; cycle.empty() || v != start; v = boundary_next[v]) {
    cycle.push_back(v);
    if (static_cast<int>(cycle.size()) > boundary_count) return fail(why, "the region's boundary is not one loop");
  }
  if (static_cast<int>(cycle.size()) != boundary_count) return fail(why, "the region has more than one boundary loop");
  if (n - disc.num_edges() + disc.num_faces() != 1) return fail(why, "the region is not a disc");
  // Start the cycle at its first corner.
  std::vector<char> is_corner(n, 0);
  for (int c : corners) is_corner[c] = 1;
  const auto first = std::find_if(cycle.begin(), cycle.end(), [&](int v) { return is_corner[v] != 0; });
  if (first == cycle.end()) return fail(why, "no corner on the region's boundary");
  std::rotate(cycle.begin(), first, cycle.end());
  const int k = static_cast<int>(cycle.size());
  std::vector<double> arc(k + 1, 0.0);
  for (int i = 1; i <= k; ++i) arc[i] = arc[i - 1] + (disc.vertex_position(cycle[i % k]) - disc.vertex_position(cycle[i - 1])).norm();
  std::vector<int> corner_at;
  for (int i = 0; i < k; ++i)
    if (is_corner[cycle[i]]) corner_at.push_back(i);
  if (corner_at.size() != corners.size() || corner_at.size() < 3)
    return fail(why, "the region's corners are not on its boundary");
  uv.assign(n, Eigen::Vector2d::Zero());
  std::vector<char> fixed(n, 0);
  auto on_circle = [&](int i) {
    const double angle = 2.0 * pi * arc[i] / arc[k];
    return Eigen::Vector2d(std::cos(angle), std::sin(angle));
  };
  for (std::size_t c = 0; c < corner_at.size(); ++c) {
    const int i0 = corner_at[c], i1 = c + 1 < corner_at.size() ? corner_at[c + 1] : k;
    const Eigen::Vector2d a = on_circle(i0), b = on_circle(i1);
    for (int i = i0; i < i1; ++i) {
      const double t = arc[i1] > arc[i0] ? (arc[i] - arc[i0]) / (arc[i1] - arc[i0]) : 0.0;
      uv[cycle[i]] = (1.0 - t) * a + t * b;
      fixed[cycle[i]] = 1;
    }
  }
  // Interior: symmetrized mean-value weights, positive wherever a face has positive angles, so
  // every interior vertex is a strict convex combination of its neighbours and, the boundary being
  // convex, the exact solution embeds the disc (Floater's theorem; Tutte's for any positive
  // weights). Solved by IC(0)-preconditioned CG; where split slivers spread the weights over many
  // orders of magnitude, rounding keeps the true residual above the tolerance and CG would restart
  // until 2n iterations, so past a budget a few times the iterations a well-conditioned disc needs
  // (about 2·√n) the system is factorized instead (sparse LDLT: exact up to rounding, the same
  // embedding). The fold check below guards rounding either way.
  const std::vector<double> mvc = mesh::mean_value_weights(disc);
  std::vector<int> unknown(n, -1);
  int count = 0;
  for (int v = 0; v < n; ++v)
    if (!fixed[v]) unknown[v] = count++;
  if (count > 0) {
    std::vector<linalg::Triplet> triplets;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(count, 2);
    for (int v = 0; v < n; ++v) {
      if (unknown[v] < 0) continue;
      double diagonal = 0.0;
      for (int h : disc.vertex_outgoing(v)) {
        const int j = disc.halfedge_vertex(h);
        const double w = std::max(0.5 * (mvc[h] + mvc[disc.halfedge_twin(h)]), 1e-12);
        diagonal += w;
        if (unknown[j] >= 0)
          triplets.push_back({unknown[v], unknown[j], -w});
        else
          rhs.row(unknown[v]) += w * uv[j].transpose();
      }
      triplets.push_back({unknown[v], unknown[v], diagonal});
    }
    const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(count, count, triplets);
    linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
    cg.set_tolerance(1e-13);
    cg.set_max_iterations(100 + static_cast<int>(5.0 * std::sqrt(static_cast<double>(count))));
    cg.compute(a);
    Eigen::MatrixXd x = cg.solve(rhs, Eigen::MatrixXd::Zero(count, 2));
    if (cg.info() != linalg::SolverInfo::Success) {
      std::vector<Eigen::Triplet<double>> lower;
      for (const linalg::Triplet& t : triplets)
        if (t.row >= t.col) lower.emplace_back(t.row, t.col, t.value);
      Eigen::SparseMatrix<double> sparse(count, count);
      sparse.setFromTriplets(lower.begin(), lower.end());
      const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt(sparse);
      if (ldlt.info() != Eigen::Success) return fail(why, "the region's map has a singular system");
      x = ldlt.solve(rhs);
    }
    for (int v = 0; v < n; ++v)
      if (unknown[v] >= 0) uv[v] = x.row(unknown[v]).transpose();
  }
  // Bijective: all faces turn the same way in the plane.
  int positive = 0, negative = 0;
  for (int f = 0; f < disc.num_faces(); ++f) {
    const auto t = disc.face_vertices(f);
    const Eigen::Vector2d e1 = uv[t[1]] - uv[t[0]], e2 = uv[t[2]] - uv[t[0]];
    const double area = e1.x() * e2.y() - e1.y() * e2.x();
    positive += area > 0.0;
    negative += area < 0.0;
  }
  if (positive > 0 && negative > 0) return fail(why, "the region's map folds");
  if (positive + negative != disc.num_faces()) return fail(why, "the region's map has a flat face");
  return true;
}

}  // namespace

bool cut_disc_chords(mesh::TriangleMesh& mesh, const std::vector<int>& region, const std::vector<int>& corners,
                     const std::vector<std::array<int, 2>>& chords, DiscChords& out, std::string* why) {
  out = DiscChords{};
  const int n0 = mesh.num_vertices(), m0 = mesh.num_faces();
  out.face_origin.resize(m0);
  for (int f = 0; f < m0; ++f) out.face_origin[f] = f;
  // The region as its own mesh, vertices in order of first use.
  std::vector<int> local(n0, -1), global;
  mesh::TriangleMesh sub;
  sub.triangles.resize(static_cast<int>(region.size()), 3);
  for (std::size_t t = 0; t < region.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(region[t], k);
      if (local[v] < 0) {
        local[v] = static_cast<int>(global.size());
        global.push_back(v);
      }
      sub.triangles(static_cast<int>(t), k) = local[v];
    }
  sub.positions.resize(static_cast<int>(global.size()), 3);
  for (std::size_t v = 0; v < global.size(); ++v) sub.positions.row(static_cast<int>(v)) = mesh.positions.row(global[v]);
  std::vector<int> local_corners;
  for (int c : corners) {
    if (local[c] < 0) return fail(why, "a corner is not in the region");
    local_corners.push_back(local[c]);
  }
  std::vector<Eigen::Vector2d> uv;
  std::vector<char> boundary;
  {
    const mesh::HalfedgeMesh disc = mesh::HalfedgeMesh::build(sub, "disc");
    if (!map_disc(disc, local_corners, uv, why)) return false;
    boundary.resize(disc.num_vertices());
    for (int v = 0; v < disc.num_vertices(); ++v) boundary[v] = disc.vertex_is_boundary(v);
  }

  // Chords one after the other on the planar copy; 3D positions follow the splits.
  mesh::TriangleMesh plane = sub;
  for (int v = 0; v < plane.num_vertices(); ++v) plane.positions.row(v) = Eigen::RowVector3d(uv[v].x(), uv[v].y(), 0.0);
  std::vector<int> origin(sub.num_faces());
  for (int f = 0; f < sub.num_faces(); ++f) origin[f] = f;
  std::vector<std::array<int, 2>> added_edge;
  std::vector<double> added_t;
  std::vector<char> frozen = boundary;
  const int n_sub = sub.num_vertices();
  for (const auto& chord : chords) {
    const int a = chord[0] >= 0 && chord[0] < n0 ? local[chord[0]] : -1;
    const int b = chord[1] >= 0 && chord[1] < n0 ? local[chord[1]] : -1;
    if (a < 0 || b < 0 || !boundary[a] || !boundary[b] || a == b) return fail(why, "a chord end is not on the region's boundary");
    const int nv = plane.num_vertices();
    const Eigen::Vector2d pa = plane.positions.row(a).head<2>().transpose(), pb = plane.positions.row(b).head<2>().transpose();
    const Eigen::Vector2d d = (pb - pa).normalized();
    std::vector<double> value(nv);
    for (int v = 0; v < nv; ++v) {
      const Eigen::Vector2d p = plane.positions.row(v).head<2>().transpose() - pa;
      value[v] = d.x() * p.y() - d.y() * p.x();
    }
    value[a] = value[b] = 0.0;
    const LevelSetSplit split = split_at_level(plane, value, {}, 0.0, 0.05, frozen);
    // 3D positions of the new vertices; bookkeeping in refined-mesh ids.
    const int nv_new = split.mesh.num_vertices();
    sub.positions.conservativeResize(nv_new, 3);
    for (int v = nv; v < nv_new; ++v) {
      const auto e = split.new_vertex_edge[v - nv];
      const double t = split.new_vertex_t[v - nv];
      sub.positions.row(v) = (1.0 - t) * sub.positions.row(e[0]) + t * sub.positions.row(e[1]);
      added_edge.push_back(e);
      added_t.push_back(t);
    }
    // An earlier chord crossed by this one gets the crossing vertex on its split edge.
    std::map<std::pair<int, int>, int> on_edge;
    for (int v = nv; v < nv_new; ++v) {
      const auto e = split.new_vertex_edge[v - nv];
      on_edge[{std::min(e[0], e[1]), std::max(e[0], e[1])}] = v;
    }
    for (auto& path : out.paths) {
      std::vector<int> longer{path.front()};
      for (std::size_t i = 1; i < path.size(); ++i) {
        const auto it = on_edge.find({std::min(path[i - 1], path[i]), std::max(path[i - 1], path[i])});
        if (it != on_edge.end()) longer.push_back(it->second);
        longer.push_back(path[i]);
      }
      path = std::move(longer);
    }
    std::vector<int> composed(split.mesh.num_faces());
    for (int f = 0; f < split.mesh.num_faces(); ++f) composed[f] = origin[split.parent_face[f]];
    origin = std::move(composed);
    plane = split.mesh;
    sub.triangles = split.mesh.triangles;
    frozen.resize(nv_new, 0);
    boundary.resize(nv_new, 0);
    // The chord: the fewest-edge path from a to b through vertices on the line.
    std::vector<std::vector<int>> adjacent(nv_new);
    for (int f = 0; f < plane.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) adjacent[plane.triangles(f, k)].push_back(plane.triangles(f, (k + 1) % 3));
    std::vector<int> from(nv_new, -2);
    std::queue<int> queue;
    from[a] = -1;
    queue.push(a);
    while (!queue.empty() && from[b] == -2) {
      const int v = queue.front();
      queue.pop();
      std::vector<int> next = adjacent[v];
      std::sort(next.begin(), next.end());
      for (int u : next) {
        if (from[u] != -2 || split.value[u] != 0.0) continue;
        if (u != b && (boundary[u] || frozen[u])) continue;
        from[u] = v;
        queue.push(u);
      }
    }
    if (from[b] == -2) return fail(why, "a chord did not become an edge path");
    std::vector<int> path;
    for (int v = b; v >= 0; v = from[v]) path.push_back(v);
    std::reverse(path.begin(), path.end());
    for (int v : path) frozen[v] = 1;
    out.paths.push_back(std::move(path));
  }
  {
    // Still one disc that keeps its orientation in the plane.
    const mesh::HalfedgeMesh check = mesh::HalfedgeMesh::build(plane, "disc");
    int positive = 0, negative = 0;
    for (int f = 0; f < check.num_faces(); ++f) {
      const auto t = check.face_vertices(f);
      const Eigen::Vector2d p0 = plane.positions.row(t[0]).head<2>().transpose();
      const Eigen::Vector2d e1 = plane.positions.row(t[1]).head<2>().transpose() - p0;
      const Eigen::Vector2d e2 = plane.positions.row(t[2]).head<2>().transpose() - p0;
      const double area = e1.x() * e2.y() - e1.y() * e2.x();
      positive += area > 0.0;
      negative += area < 0.0;
    }
    if ((positive > 0 && negative > 0) || positive + negative != check.num_faces())
      return fail(why, "a chord split folded the region's map");
  }

  // Back into the mesh: added vertices appended, a split face's first part keeps its id.
  for (int v = n_sub; v < sub.num_vertices(); ++v) global.push_back(n0 + (v - n_sub));
  const int n1 = n0 + (sub.num_vertices() - n_sub);
  mesh.positions.conservativeResize(n1, 3);
  for (int v = n_sub; v < sub.num_vertices(); ++v) mesh.positions.row(global[v]) = sub.positions.row(v);
  for (std::size_t k = 0; k < added_edge.size(); ++k) {
    out.new_vertex_edge.push_back({global[added_edge[k][0]], global[added_edge[k][1]]});
    out.new_vertex_t.push_back(added_t[k]);
  }
  std::vector<char> reused(region.size(), 0);
  std::vector<std::array<int, 3>> appended;
  for (int f = 0; f < sub.num_faces(); ++f) {
    const std::array<int, 3> t = {global[sub.triangles(f, 0)], global[sub.triangles(f, 1)], global[sub.triangles(f, 2)]};
    const int o = origin[f];
    if (!reused[o]) {
      reused[o] = 1;
      for (int k = 0; k < 3; ++k) mesh.triangles(region[o], k) = t[k];
    } else {
      appended.push_back(t);
      out.face_origin.push_back(region[o]);
    }
  }
  mesh.triangles.conservativeResize(m0 + static_cast<int>(appended.size()), 3);
  for (std::size_t f = 0; f < appended.size(); ++f)
    for (int k = 0; k < 3; ++k) mesh.triangles(m0 + static_cast<int>(f), k) = appended[f][k];
  for (auto& path : out.paths)
    for (int& v : path) v = global[v];
  return true;
}

void interpolate_added_vertices(const DiscChords& chords, std::vector<double>& data) {
  for (std::size_t k = 0; k < chords.new_vertex_edge.size(); ++k) {
    const auto e = chords.new_vertex_edge[k];
    const double t = chords.new_vertex_t[k];
    data.push_back((1.0 - t) * data[e[0]] + t * data[e[1]]);
  }
}

}  // namespace volspline::polycube
