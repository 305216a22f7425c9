// SPDX-License-Identifier: MIT
#include "core/polycube/morse_function.h"

#include <algorithm>
#include <cassert>
#include <functional>
#include <limits>

#include "core/linalg/algebraic_multigrid.h"
#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/mesh/edge_weights.h"
#include "core/mesh/graph_distance.h"
#include "core/mesh/mesh_geometry.h"

namespace volspline::polycube {

namespace {

// The vertex farthest from `from` by the graph distances d from it (the first on ties).
int farthest_vertex(const mesh::HalfedgeMesh& mesh, int from, const mesh::GraphDistances& d) {
  int best = from;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (d.distance[v] != std::numeric_limits<double>::infinity() && d.distance[v] > d.distance[best]) best = v;
  return best;
}

// Maxima of d (per vertex, finite) whose superlevel-set component lives at least `threshold`
// (0-dimensional persistence by a union–find sweep from the top; the global maximum is left
// out, it never dies). Ascending ids.
std::vector<int> persistent_maxima(const mesh::HalfedgeMesh& mesh, const std::vector<double>& d, double threshold) {
  const int n = mesh.num_vertices();
  std::vector<int> order;
  for (int v = 0; v < n; ++v)
    if (mesh.vertex_halfedge(v) != mesh::no_id) order.push_back(v);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return d[a] > d[b] || (d[a] == d[b] && a < b); });
  std::vector<int> parent(n, -1), top(n, -1);
  std::function<int(int)> find = [&](int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
  std::vector<int> out;
  for (int v : order) {
    parent[v] = v;
    top[v] = v;
    for (int u : mesh.vertex_neighbors(v)) {
      if (parent[u] < 0) continue;
      int a = find(u), b = find(v);
      if (a == b) continue;
      // The component with the lower top dies here.
      if (d[top[a]] < d[top[b]] || (d[top[a]] == d[top[b]] && top[a] > top[b])) std::swap(a, b);
      if (d[top[b]] - d[v] >= threshold && top[b] != v) out.push_back(top[b]);
      parent[b] = a;
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// (value, id) order: the symbolic perturbation that makes every vertex value distinct.
bool lower(const std::vector<double>& f, int a, int b) { return f[a] < f[b] || (f[a] == f[b] && a < b); }

}  // namespace

void classify_critical_points(const mesh::HalfedgeMesh& mesh, MorseFunction& function) {
  const int n = mesh.num_vertices();
  const std::vector<double>& f = function.value;
  function.kind.assign(n, CriticalKind::Regular);
  function.multiplicity.assign(n, 0);
  function.num_minima = function.num_maxima = function.num_saddles = 0;
  std::vector<char> ring;
  for (int v = 0; v < n; ++v) {
    if (mesh.vertex_halfedge(v) == mesh::no_id) continue;
    ring.clear();
    for (int u : mesh.vertex_neighbors(v)) ring.push_back(lower(f, u, v) ? 0 : 1);
    int changes = 0;
    for (std::size_t i = 0; i < ring.size(); ++i) changes += ring[i] != ring[(i + 1) % ring.size()];
    if (changes == 0) {
      if (ring[0] == 1) {
        function.kind[v] = CriticalKind::Minimum;
        ++function.num_minima;
      } else {
        function.kind[v] = CriticalKind::Maximum;
        ++function.num_maxima;
      }
    } else if (changes > 2) {
      function.kind[v] = CriticalKind::Saddle;
      function.multiplicity[v] = changes / 2 - 1;
      function.num_saddles += changes / 2 - 1;
    }
  }
}

MorsePoles morse_poles(const mesh::HalfedgeMesh& mesh, double limb_persistence, double pole_offset) {
  const int n = mesh.num_vertices();
  assert(n >= 4);
  int start = 0;
  while (start < n && mesh.vertex_halfedge(start) == mesh::no_id) ++start;
  MorsePoles poles;
  // Two sweeps: the second one's distances also give the limbs' persistence.
  const std::vector<double> length = mesh::edge_lengths(mesh);
  poles.source = farthest_vertex(mesh, start, mesh::graph_distances(mesh, {start}, length));
  mesh::GraphDistances from_source = mesh::graph_distances(mesh, {poles.source}, length);
  poles.sink = farthest_vertex(mesh, poles.source, from_source);
  if (pole_offset > 0.0) {
    // The vertex farthest by `d` among those at least `radius` from another by `from_other`.
    auto farthest_off = [&](const mesh::GraphDistances& d, const mesh::GraphDistances& from_other, double radius,
                            int fallback) {
      int best = -1;
      for (int v = 0; v < n; ++v) {
        if (d.distance[v] == std::numeric_limits<double>::infinity() || from_other.distance[v] < radius) continue;
        if (best < 0 || d.distance[v] > d.distance[best]) best = v;
      }
      return best < 0 ? fallback : best;
    };
    const double radius = pole_offset * from_source.distance[poles.sink];
    const int diameter_source = poles.source;
    poles.sink = farthest_off(from_source, mesh::graph_distances(mesh, {poles.sink}, length), radius, poles.sink);
    poles.source =
        farthest_off(mesh::graph_distances(mesh, {poles.sink}, length), from_source, radius, diameter_source);
    from_source = mesh::graph_distances(mesh, {poles.source}, length);
  }
  if (limb_persistence > 0.0) {
    for (int v : persistent_maxima(mesh, from_source.distance, limb_persistence * from_source.distance[poles.sink]))
      if (v != poles.source && v != poles.sink) poles.limb_tips.push_back(v);
  }
  return poles;
}

// Iterations per restart of the harmonic solve, by preconditioner (see compute_morse_function).
constexpr int kMultigridChunk = 100;
constexpr int kIncompleteCholeskyChunk = 1000;

MorseFunction compute_morse_function(const mesh::HalfedgeMesh& mesh, const MorseFunctionOptions& options) {
  const int n = mesh.num_vertices();
  MorseFunction function;
  const MorsePoles poles = morse_poles(mesh, options.limb_persistence, options.pole_offset);
  function.source = poles.source;
  function.sink = poles.sink;
  function.limb_tips = poles.limb_tips;
  std::vector<char> pole(n, 0);
  pole[function.source] = pole[function.sink] = 1;
  for (int v : function.limb_tips) pole[v] = 1;

  const std::vector<double> mvc = mesh::mean_value_weights(mesh);
  std::vector<int> unknown(n, -1);
  int m = 0;
  for (int v = 0; v < n; ++v)
    if (!pole[v] && mesh.vertex_halfedge(v) != mesh::no_id) unknown[v] = m++;
  function.value.assign(n, 0.0);
  function.value[function.sink] = 1.0;
  for (int v : function.limb_tips) function.value[v] = 1.0;
  std::vector<linalg::Triplet> triplets;
  triplets.reserve(7 * static_cast<std::size_t>(m));
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  for (int v = 0; v < n; ++v) {
    if (unknown[v] < 0) continue;
    double diagonal = 0.0;
    for (int h : mesh.vertex_outgoing(v)) {
      const int u = mesh.halfedge_vertex(h);
      // Symmetrized mean-value weights: positive (maximum principle) and an SPD system.
      const double w = 0.5 * (mvc[h] + mvc[mesh.halfedge_twin(h)]);
      diagonal += w;
      if (unknown[u] >= 0)
        triplets.push_back({unknown[v], unknown[u], -w});
      else
        rhs(unknown[v]) += w * function.value[u];
    }
    triplets.push_back({unknown[v], unknown[v], diagonal > 0.0 ? diagonal : 1.0});
  }
  const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(m, m, triplets);
  // The relative residual cannot fall much below √m·ε in double precision (6.9e-14 at 97k
  // unknowns, 1.2e-13 at 288k): a tolerance near that floor would run CG to its iteration cap
  // (a drilled cube's 97k unknowns with IC(0): a cap of 388k iterations, past 20 minutes). Chunks of
  // iterations, each restarted from the last iterate, stop at the tolerance or once a chunk no
  // longer halves the residual. IC(0)'s CG iterations grow like √n (kitten's 10k unknowns: 250
  // to the tolerance), smoothed-aggregation multigrid keeps them about constant (some 30 a
  // decade) and takes over from MorseFunctionOptions::multigrid_from unknowns.
  auto run = [&](auto& cg, int chunk_iterations) {
    cg.set_tolerance(options.tolerance);
    cg.set_max_iterations(chunk_iterations);
    cg.compute(a);
    Eigen::VectorXd x = Eigen::VectorXd::Constant(m, 0.5);
    double last = std::numeric_limits<double>::infinity();
    for (int chunk = 0; chunk < std::max(10, 4 * m / chunk_iterations); ++chunk) {
      x = cg.solve(rhs, x);
      if (cg.info() == linalg::SolverInfo::Success || !(cg.residual() < 0.5 * last)) break;
      last = cg.residual();
    }
    return x;
  };
  Eigen::VectorXd x;
  if (m >= options.multigrid_from) {
    linalg::ConjugateGradient<linalg::AlgebraicMultigrid> cg;
    x = run(cg, kMultigridChunk);
  } else {
    linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
    x = run(cg, kIncompleteCholeskyChunk);
  }
  for (int v = 0; v < n; ++v)
    if (unknown[v] >= 0) function.value[v] = std::clamp(x(unknown[v]), 0.0, 1.0);
  classify_critical_points(mesh, function);
  return function;
}

}  // namespace volspline::polycube
