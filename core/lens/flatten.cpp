// SPDX-License-Identifier: MIT
#include "core/lens/flatten.h"

#include <chrono>
#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/common/error.h"

namespace volspline::lens {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Per-triangle constants: the inverse of the standard triangle's edge matrix and, per edge
// (0→1, 1→2, 2→0), its weight and its vector in the standard triangle.
struct StandardTriangle {
  Eigen::Matrix2d edges_inverse;
  double weight[3];
  Eigen::Vector2d rest[3];
};

}  // namespace

FlattenResult flatten_lens(const mesh::Positions& xyz, const mesh::Triangles& triangles,
                           const std::vector<char>& pinned, const Eigen::MatrixX2d& start,
                           const FlattenOptions& options, const pipeline::Progress& progress) {
  const auto t_setup = std::chrono::steady_clock::now();
  const int n = static_cast<int>(xyz.rows());
  const int m = static_cast<int>(triangles.rows());
  FlattenResult result;
  result.positions = start;

  std::vector<int> free_id(n, -1);
  int num_free = 0;
  for (int v = 0; v < n; ++v)
    if (!pinned[v]) free_id[v] = num_free++;
  if (num_free == 0) return result;

  // Step 1: standard 2D triangles T^d: v0 = (0,0), v1 = (|e1|, 0), v2 = (|e3|cosθ, |e3|sinθ).
  std::vector<StandardTriangle> standard(m);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(std::size_t(m) * 12);
  Eigen::MatrixX2d pinned_rhs = Eigen::MatrixX2d::Zero(num_free, 2);
  for (int t = 0; t < m; ++t) {
    const int v[3] = {triangles(t, 0), triangles(t, 1), triangles(t, 2)};
    const Eigen::Vector3d e1 = xyz.row(v[1]) - xyz.row(v[0]), e3 = xyz.row(v[2]) - xyz.row(v[0]);
    const double l1 = e1.norm(), l3 = e3.norm();
    const double cos_t = e1.dot(e3) / (l1 * l3), sin_t = e1.cross(e3).norm() / (l1 * l3);
    const Eigen::Vector2d p[3] = {{0, 0}, {l1, 0}, {l3 * cos_t, l3 * sin_t}};
    StandardTriangle& s = standard[t];
    Eigen::Matrix2d edges;
    edges << p[1] - p[0], p[2] - p[0];
    s.edges_inverse = edges.inverse();
    const double area = 0.5 * l1 * l3 * sin_t;
    const double h = (xyz(v[0], 2) + xyz(v[1], 2) + xyz(v[2], 2)) / (3.0 * options.height_unit);
    for (int e = 0; e < 3; ++e) {
      const int i = e, j = (e + 1) % 3, k = (e + 2) % 3;
      const Eigen::Vector2d a = p[i] - p[k], b = p[j] - p[k];
      const double cot = a.dot(b) / std::abs(a.x() * b.y() - a.y() * b.x());
      // §6.4 weights: w_ij = (1 + h_k)·A_k·cotθ, θ opposite the edge in T_k.
      const double w = (1.0 + h) * area * cot;
      s.weight[e] = w;
      s.rest[e] = p[j] - p[i];
      const int vi = v[i], vj = v[j], fi = free_id[vi], fj = free_id[vj];
      if (fi >= 0) triplets.emplace_back(fi, fi, w);
      if (fj >= 0) triplets.emplace_back(fj, fj, w);
      if (fi >= 0 && fj >= 0) {
        triplets.emplace_back(fi, fj, -w);
        triplets.emplace_back(fj, fi, -w);
      } else if (fi >= 0) {
        pinned_rhs.row(fi) += w * start.row(vj);
      } else if (fj >= 0) {
        pinned_rhs.row(fj) += w * start.row(vi);
      }
    }
  }
  Eigen::SparseMatrix<double> W(num_free, num_free);
  W.setFromTriplets(triplets.begin(), triplets.end());
  result.ms_setup = ms_since(t_setup);

  // Algorithm 5: W depends only on the lens mesh, so it is factorized once and reused.
  const auto t_factor = std::chrono::steady_clock::now();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> solver;
  solver.compute(W);
  if (solver.info() != Eigen::Success)
    throw Error("lens flattening: the system matrix is singular (a free region touches no pinned vertex?)");
  result.ms_factorize = ms_since(t_factor);

  const auto t_iterate = std::chrono::steady_clock::now();
  Eigen::MatrixX2d& x = result.positions;
  Eigen::MatrixX2d rhs(num_free, 2), solution(num_free, 2);
  std::vector<Eigen::Matrix2d> metric(m);
  double previous_energy = 0;
  for (int it = 0; it < options.max_iterations; ++it) {
    // Local step (§6.4.1). J maps T^d onto the current triangle; its closest rotation (the polar
    // factor UVᵀ of Eq. 6.6, closed form in 2D) and closest similarity (Eq. 6.7) share the angle
    // θ = atan2(J10 − J01, J00 + J11), so θ_r = θ_a and Eq. 6.8 only blends the scale.
    // J is the exact affine Jacobian rather than Eq. 6.5's unweighted edge sum, so the local step
    // minimizes the cot-weighted Eq. 6.2 per triangle exactly and the energy never increases.
    rhs = pinned_rhs;
    for (int t = 0; t < m; ++t) {
      const int v0 = triangles(t, 0), v1 = triangles(t, 1), v2 = triangles(t, 2);
      Eigen::Matrix2d current;
      current << (x.row(v1) - x.row(v0)).transpose(), (x.row(v2) - x.row(v0)).transpose();
      const Eigen::Matrix2d J = current * standard[t].edges_inverse;
      const double a = 0.5 * (J(0, 0) + J(1, 1)), b = 0.5 * (J(1, 0) - J(0, 1));
      const double sigma1 = std::hypot(a, b);
      Eigen::Matrix2d M = Eigen::Matrix2d::Identity();
      if (sigma1 > 0) {
        const double sigma = options.alpha * (sigma1 - 1.0) + 1.0;  // Eq. 6.8
        M << a, -b, b, a;
        M *= sigma / sigma1;
      }
      metric[t] = M;
      const int v[3] = {v0, v1, v2};
      for (int e = 0; e < 3; ++e) {
        const Eigen::RowVector2d r = standard[t].weight[e] * (M * standard[t].rest[e]).transpose();
        const int fi = free_id[v[e]], fj = free_id[v[(e + 1) % 3]];
        if (fi >= 0) rhs.row(fi) -= r;
        if (fj >= 0) rhs.row(fj) += r;
      }
    }
    // Global step: Eq. 6.3 with the pre-factorized W.
    solution = solver.solve(rhs);
    for (int v = 0; v < n; ++v)
      if (free_id[v] >= 0) x.row(v) = solution.row(free_id[v]);

    double energy = 0;  // Eq. 6.2
    for (int t = 0; t < m; ++t) {
      const int v[3] = {triangles(t, 0), triangles(t, 1), triangles(t, 2)};
      for (int e = 0; e < 3; ++e) {
        const Eigen::Vector2d d = (x.row(v[(e + 1) % 3]) - x.row(v[e])).transpose() - metric[t] * standard[t].rest[e];
        energy += standard[t].weight[e] * d.squaredNorm();
      }
    }
    result.iterations = it + 1;
    result.energy = energy;
    if (it > 0 && std::abs(energy - previous_energy) <= options.tol_rel * previous_energy) {
      result.converged = true;
      break;
    }
    previous_energy = energy;
    progress.report("flatten", double(it + 1) / options.max_iterations);
  }
  result.ms_iterations = ms_since(t_iterate);
  return result;
}

}  // namespace volspline::lens
