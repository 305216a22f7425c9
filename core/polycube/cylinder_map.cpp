// SPDX-License-Identifier: MIT
#include "core/polycube/cylinder_map.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/mesh/edge_weights.h"
#include "core/mesh/graph_distance.h"

namespace volspline::polycube {

namespace {

double loop_length(const mesh::HalfedgeMesh& m, const std::vector<int>& loop) {
  double total = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i)
    total += (m.vertex_position(loop[(i + 1) % loop.size()]) - m.vertex_position(loop[i])).norm();
  return total;
}

}  // namespace

CylinderMap compute_cylinder_map(const mesh::HalfedgeMesh& mesh, const std::vector<int>& loop_a,
                                 const std::vector<int>& loop_b) {
  const int n = mesh.num_vertices();
  CylinderMap out;
  out.circumference = 0.5 * (loop_length(mesh, loop_a) + loop_length(mesh, loop_b));
  std::vector<char> in_a(n, 0), in_b(n, 0);
  for (int v : loop_a) in_a[v] = 1;
  for (int v : loop_b) in_b[v] = 1;
  // Cut: the shortest edge path from loop A to loop B.
  const mesh::GraphDistances from_a = mesh::graph_distances(mesh, loop_a);
  int end = -1;
  for (int v : loop_b)
    if (end < 0 || from_a.distance[v] < from_a.distance[end]) end = v;
  out.cut = mesh::graph_path(from_a, end);
  const std::vector<int>& path = out.cut;
  out.length = from_a.distance[end];
  assert(path.size() >= 2);
  std::vector<int> on_path(n, -1);
  for (std::size_t i = 0; i < path.size(); ++i) on_path[path[i]] = static_cast<int>(i);
  auto is_path_edge = [&](int h) {
    const int a = mesh.halfedge_source(h), b = mesh.halfedge_vertex(h);
    return on_path[a] >= 0 && on_path[b] >= 0 && std::abs(on_path[a] - on_path[b]) == 1;
  };
  // Faces on the left of the path (the face of each forward path halfedge), extended around
  // each path vertex without crossing a path or boundary edge: they use the duplicated copy.
  std::vector<char> left(mesh.num_faces(), 0);
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    for (int h : mesh.vertex_outgoing(path[i]))
      if (mesh.halfedge_vertex(h) == path[i + 1]) left[mesh.halfedge_face(h)] = 1;
  for (int p : path) {
    bool grew = true;
    while (grew) {
      grew = false;
      for (int h : mesh.vertex_outgoing(p)) {
        // h and the next outgoing halfedge CCW (twin(prev(h))) bound the face of h; the face
        // across h is face(twin(h)). Spread across h if h is not a path or boundary edge.
        const int f = mesh.halfedge_face(h);
        const int g = mesh.halfedge_face(mesh.halfedge_twin(h));
        if (f < 0 || g < 0 || is_path_edge(h)) continue;
        if (left[f] != left[g]) {
          left[f] = left[g] = 1;
          grew = true;
        }
      }
    }
  }
  // The cut disc: path vertices get a copy (id n + index along the path) on the left faces.
  const int m = n + static_cast<int>(path.size());
  auto disc_vertex = [&](int f, int v) { return on_path[v] >= 0 && left[f] ? n + on_path[v] : v; };
  // Boundary values: A (u = 0) and B (u = 1) by arc length from the right copy (v = 0) of the
  // cut's end to its left copy (v = 1); the cut's right side v = 0, its left side v = 1.
  std::vector<double> bu(m, 0.0), bv(m, 0.0);
  std::vector<char> fixed(m, 0);
  std::vector<double> arc(path.size(), 0.0);
  for (std::size_t i = 1; i < path.size(); ++i)
    arc[i] = arc[i - 1] + (mesh.vertex_position(path[i]) - mesh.vertex_position(path[i - 1])).norm();
  for (std::size_t i = 0; i < path.size(); ++i) {
    const double t = arc.back() > 0.0 ? arc[i] / arc.back() : 0.0;
    bu[path[i]] = bu[n + i] = t;
    bv[path[i]] = 0.0;
    bv[n + i] = 1.0;
    fixed[path[i]] = fixed[n + i] = 1;
  }
  // Walk each loop away from the cut end in the direction that leaves the right side first:
  // the loop's boundary halfedges run one way; the right copy's neighbour along the loop is the
  // one whose boundary edge borders a right face.
  auto walk_loop = [&](const std::vector<int>& loop, int start, double u_value) {
    const int k = static_cast<int>(loop.size());
    int pos = static_cast<int>(std::find(loop.begin(), loop.end(), start) - loop.begin());
    // Direction: the loop edge (start, next) whose interior face is a right face.
    int direction = 1;
    for (int h : mesh.vertex_outgoing(start)) {
      if (mesh.halfedge_vertex(h) != loop[(pos + 1) % k]) continue;
      int f = mesh.halfedge_face(h);
      if (f < 0) f = mesh.halfedge_face(mesh.halfedge_twin(h));
      if (left[f]) direction = -1;
    }
    std::vector<int> order;
    for (int i = 0; i <= k; ++i) order.push_back(loop[((pos + direction * i) % k + k) % k]);
    double total = 0.0;
    std::vector<double> s(order.size(), 0.0);
    for (std::size_t i = 1; i < order.size(); ++i)
      s[i] = s[i - 1] + (mesh.vertex_position(order[i]) - mesh.vertex_position(order[i - 1])).norm();
    total = s.back();
    for (std::size_t i = 1; i + 1 < order.size(); ++i) {
      bu[order[i]] = u_value;
      bv[order[i]] = total > 0.0 ? s[i] / total : 0.0;
      fixed[order[i]] = 1;
    }
  };
  walk_loop(loop_a, path.front(), 0.0);
  walk_loop(loop_b, path.back(), 1.0);

  // Floater map on the disc: symmetrized mean-value weights (positive, SPD).
  const std::vector<double> mvc = mesh::mean_value_weights(mesh);
  std::vector<int> unknown(m, -1);
  int count = 0;
  for (int v = 0; v < n; ++v)
    if (!fixed[v] && mesh.vertex_halfedge(v) != mesh::no_id) unknown[v] = count++;
  std::vector<linalg::Triplet> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(count, 2);
  for (int v = 0; v < n; ++v) {
    if (unknown[v] < 0) continue;
    double diagonal = 0.0;
    for (int h : mesh.vertex_outgoing(v)) {
      const int f = mesh.halfedge_face(h) >= 0 ? mesh.halfedge_face(h) : mesh.halfedge_face(mesh.halfedge_twin(h));
      const int j = disc_vertex(f, mesh.halfedge_vertex(h));
      const double w = 0.5 * (mvc[h] + mvc[mesh.halfedge_twin(h)]);
      diagonal += w;
      if (unknown[j] >= 0)
        triplets.push_back({unknown[v], unknown[j], -w});
      else
        rhs.row(unknown[v]) += w * Eigen::RowVector2d(bu[j], bv[j]);
    }
    triplets.push_back({unknown[v], unknown[v], diagonal > 0.0 ? diagonal : 1.0});
  }
  out.u.assign(n, 0.0);
  out.v.assign(n, 0.0);
  for (int v = 0; v < n; ++v)
    if (fixed[v]) {
      out.u[v] = bu[v];
      out.v[v] = bv[v];
    }
  if (count > 0) {
    const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(count, count, triplets);
    linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
    cg.set_tolerance(1e-10);
    cg.compute(a);
    const Eigen::MatrixXd x = cg.solve(rhs, Eigen::MatrixXd::Constant(count, 2, 0.5));
    for (int v = 0; v < n; ++v)
      if (unknown[v] >= 0) {
        out.u[v] = x(unknown[v], 0);
        out.v[v] = x(unknown[v], 1);
      }
  }
  for (double& v : out.v) v -= std::floor(v);
  return out;
}

}  // namespace volspline::polycube
