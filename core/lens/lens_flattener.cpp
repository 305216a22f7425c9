// SPDX-License-Identifier: MIT
#include "core/lens/lens_flattener.h"

#include <chrono>
#include <cmath>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/common/error.h"

namespace volspline::lens {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Per-triangle constants of an active triangle (one with a free vertex): its vertices, the
// inverse of the standard triangle's edge matrix and, per edge (0→1, 1→2, 2→0), its weight and
// its vector in the standard triangle.
struct StandardTriangle {
  int v[3];
  double inv00, inv01, inv10, inv11;
  double weight[3];
  double rest_x[3], rest_y[3];
};

using Solver = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>>;

}  // namespace

struct LensFlattener::State {
  int n = 0;
  int num_free = 0;
  std::vector<int> free_id;
  std::vector<StandardTriangle> standard;
  Solver solver;
  double ms_setup = 0, ms_factorize = 0;
};

LensFlattener::LensFlattener() = default;
LensFlattener::~LensFlattener() = default;
LensFlattener::LensFlattener(LensFlattener&&) noexcept = default;
LensFlattener& LensFlattener::operator=(LensFlattener&&) noexcept = default;

bool LensFlattener::ready() const { return state_ != nullptr; }
int LensFlattener::vertices() const { return state_ ? state_->n : 0; }
double LensFlattener::ms_setup() const { return state_ ? state_->ms_setup : 0.0; }
double LensFlattener::ms_factorize() const { return state_ ? state_->ms_factorize : 0.0; }

void LensFlattener::compute(const mesh::Positions& xyz, const mesh::Triangles& triangles,
                            const std::vector<char>& pinned, double height_unit) {
  state_.reset();
  const auto t_setup = std::chrono::steady_clock::now();
  auto state = std::make_unique<State>();
  const int n = static_cast<int>(xyz.rows());
  const int m = static_cast<int>(triangles.rows());
  state->n = n;
  state->free_id.assign(n, -1);
  int num_free = 0;
  for (int v = 0; v < n; ++v)
    if (!pinned[v]) state->free_id[v] = num_free++;
  state->num_free = num_free;
  if (num_free == 0) {
    state_ = std::move(state);
    return;
  }
  const std::vector<int>& free_id = state->free_id;

  // Step 1: standard 2D triangles T^d: v0 = (0,0), v1 = (|e1|, 0), v2 = (|e3|cosθ, |e3|sinθ).
  // A triangle with three pinned vertices neither enters W nor changes, so only active ones are kept.
  std::vector<StandardTriangle>& standard = state->standard;
  standard.reserve(std::size_t(m) / 2);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(std::size_t(num_free) * 14);
  for (int t = 0; t < m; ++t) {
    const int v[3] = {triangles(t, 0), triangles(t, 1), triangles(t, 2)};
    if (free_id[v[0]] < 0 && free_id[v[1]] < 0 && free_id[v[2]] < 0) continue;
    const Eigen::Vector3d e1 = xyz.row(v[1]) - xyz.row(v[0]), e3 = xyz.row(v[2]) - xyz.row(v[0]);
    const double l1 = e1.norm(), l3 = e3.norm();
    const double cos_t = e1.dot(e3) / (l1 * l3), sin_t = e1.cross(e3).norm() / (l1 * l3);
    const double px[3] = {0, l1, l3 * cos_t}, py[3] = {0, 0, l3 * sin_t};
    StandardTriangle s;
    for (int k = 0; k < 3; ++k) s.v[k] = v[k];
    const double det = px[1] * py[2] - px[2] * py[1];
    s.inv00 = py[2] / det, s.inv01 = -px[2] / det, s.inv10 = -py[1] / det, s.inv11 = px[1] / det;
    const double area = 0.5 * l1 * l3 * sin_t;
    const double h = (xyz(v[0], 2) + xyz(v[1], 2) + xyz(v[2], 2)) / (3.0 * height_unit);
    for (int e = 0; e < 3; ++e) {
      const int i = e, j = (e + 1) % 3, k = (e + 2) % 3;
      const double ax = px[i] - px[k], ay = py[i] - py[k], bx = px[j] - px[k], by = py[j] - py[k];
      const double cot = (ax * bx + ay * by) / std::abs(ax * by - ay * bx);
      // §6.4 weights: w_ij = (1 + h_k)·A_k·cotθ, θ opposite the edge in T_k.
      const double w = (1.0 + h) * area * cot;
      s.weight[e] = w;
      s.rest_x[e] = px[j] - px[i];
      s.rest_y[e] = py[j] - py[i];
      const int fi = free_id[v[i]], fj = free_id[v[j]];
      if (fi >= 0) triplets.emplace_back(fi, fi, w);
      if (fj >= 0) triplets.emplace_back(fj, fj, w);
      if (fi >= 0 && fj >= 0) {
        triplets.emplace_back(fi, fj, -w);
        triplets.emplace_back(fj, fi, -w);
      }
    }
    standard.push_back(s);
  }
  Eigen::SparseMatrix<double> W(num_free, num_free);
  W.setFromTriplets(triplets.begin(), triplets.end());
  state->ms_setup = ms_since(t_setup);

  // Algorithm 5: W depends only on the lens mesh, so it is factorized once and reused by every
  // flatten(); the x and y columns of Eq. 6.3 share the factorization.
  const auto t_factor = std::chrono::steady_clock::now();
  state->solver.compute(W);
  if (state->solver.info() != Eigen::Success)
    throw Error("lens flattening: the system matrix is singular (a free region touches no pinned vertex?)");
  state->ms_factorize = ms_since(t_factor);
  state_ = std::move(state);
}

FlattenResult LensFlattener::flatten(const Eigen::MatrixX2d& start, const FlattenOptions& options,
                                     const Progress& progress) const {
  if (!state_) throw Error("lens flattening: flatten() called before a successful compute()");
  const State& st = *state_;
  if (start.rows() != st.n)
    throw Error("lens flattening: start has " + std::to_string(start.rows()) + " rows, the mesh has " +
                std::to_string(st.n) + " vertices");
  FlattenResult result;
  result.positions = start;
  if (st.num_free == 0) return result;
  result.ms_setup = st.ms_setup;
  result.ms_factorize = st.ms_factorize;

  const auto t_iterate = std::chrono::steady_clock::now();
  const std::vector<int>& free_id = st.free_id;
  const std::vector<StandardTriangle>& standard = st.standard;
  const std::size_t num_active = standard.size();
  // Right-hand side of Eq. 6.3 from the pinned neighbours (same order of sums as the assembly).
  Eigen::MatrixX2d pinned_rhs = Eigen::MatrixX2d::Zero(st.num_free, 2);
  for (std::size_t t = 0; t < num_active; ++t) {
    const StandardTriangle& s = standard[t];
    for (int e = 0; e < 3; ++e) {
      const int vi = s.v[e], vj = s.v[(e + 1) % 3], fi = free_id[vi], fj = free_id[vj];
      const double w = s.weight[e];
      if (fi >= 0 && fj < 0) pinned_rhs.row(fi) += w * start.row(vj);
      else if (fj >= 0 && fi < 0) pinned_rhs.row(fj) += w * start.row(vi);
    }
  }

  Eigen::MatrixX2d& x = result.positions;
  Eigen::MatrixX2d rhs(st.num_free, 2), solution(st.num_free, 2);
  std::vector<double> metric_a(num_active), metric_b(num_active);  // M = [a −b; b a] per triangle
  double previous_energy = 0;
  for (int it = 0; it < options.max_iterations; ++it) {
    // Local step (§6.4.1). J maps T^d onto the current triangle; its closest rotation (the polar
    // factor UVᵀ of Eq. 6.6, closed form in 2D) and closest similarity (Eq. 6.7) share the angle
    // θ = atan2(J10 − J01, J00 + J11), so θ_r = θ_a and Eq. 6.8 only blends the scale.
    // J is the exact affine Jacobian rather than Eq. 6.5's unweighted edge sum, so the local step
    // minimizes the cot-weighted Eq. 6.2 per triangle exactly and the energy never increases.
    rhs = pinned_rhs;
    for (std::size_t t = 0; t < num_active; ++t) {
      const StandardTriangle& s = standard[t];
      const double c0x = x(s.v[1], 0) - x(s.v[0], 0), c0y = x(s.v[1], 1) - x(s.v[0], 1);
      const double c1x = x(s.v[2], 0) - x(s.v[0], 0), c1y = x(s.v[2], 1) - x(s.v[0], 1);
      const double j00 = c0x * s.inv00 + c1x * s.inv10, j01 = c0x * s.inv01 + c1x * s.inv11;
      const double j10 = c0y * s.inv00 + c1y * s.inv10, j11 = c0y * s.inv01 + c1y * s.inv11;
      double a = 0.5 * (j00 + j11), b = 0.5 * (j10 - j01);
      const double sigma1 = std::hypot(a, b);
      if (sigma1 > 0) {
        const double sigma = options.alpha * (sigma1 - 1.0) + 1.0;  // Eq. 6.8
        a *= sigma / sigma1;
        b *= sigma / sigma1;
      } else {
        a = 1.0, b = 0.0;
      }
      metric_a[t] = a, metric_b[t] = b;
      for (int e = 0; e < 3; ++e) {
        const double w = s.weight[e];
        const double rx = w * (a * s.rest_x[e] - b * s.rest_y[e]), ry = w * (b * s.rest_x[e] + a * s.rest_y[e]);
        const int fi = free_id[s.v[e]], fj = free_id[s.v[(e + 1) % 3]];
        if (fi >= 0) rhs(fi, 0) -= rx, rhs(fi, 1) -= ry;
        if (fj >= 0) rhs(fj, 0) += rx, rhs(fj, 1) += ry;
      }
    }
    // Global step: Eq. 6.3 with the pre-factorized W.
    solution = st.solver.solve(rhs);
    for (int v = 0; v < st.n; ++v)
      if (free_id[v] >= 0) x(v, 0) = solution(free_id[v], 0), x(v, 1) = solution(free_id[v], 1);

    double energy = 0;  // Eq. 6.2 (inactive triangles are rigidly in place and add zero)
    for (std::size_t t = 0; t < num_active; ++t) {
      const StandardTriangle& s = standard[t];
      const double a = metric_a[t], b = metric_b[t];
      for (int e = 0; e < 3; ++e) {
        const int i = s.v[e], j = s.v[(e + 1) % 3];
        const double dx = x(j, 0) - x(i, 0) - (a * s.rest_x[e] - b * s.rest_y[e]);
        const double dy = x(j, 1) - x(i, 1) - (b * s.rest_x[e] + a * s.rest_y[e]);
        energy += s.weight[e] * (dx * dx + dy * dy);
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
