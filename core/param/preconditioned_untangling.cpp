// SPDX-License-Identifier: MIT
#include "core/param/preconditioned_untangling.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

#include <Eigen/SparseCholesky>

namespace volspline::param {

namespace {

using RowMajorX3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// z = M⁻¹ v per coordinate, v and z as 3·n vectors (x, y, z per node).
class MetricSolver {
 public:
  explicit MetricSolver(const Eigen::SparseMatrix<double>& metric) : identity_(metric.rows() == 0) {
    if (!identity_) llt_.compute(metric);
  }
  bool ok() const { return identity_ || llt_.info() == Eigen::Success; }
  bool identity() const { return identity_; }
  Eigen::VectorXd solve(const Eigen::VectorXd& v) const {
    if (identity_) return v;
    const Eigen::Index n = v.size() / 3;
    const RowMajorX3 z = llt_.solve(Eigen::Map<const RowMajorX3>(v.data(), n, 3));
    return Eigen::Map<const Eigen::VectorXd>(z.data(), v.size());
  }

 private:
  bool identity_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> llt_;
};

// Without a metric and curvature pairs, the first step moves the worst unknown by 1e-2 (units
// of x), as untangle.
Eigen::VectorXd first_direction(const MetricSolver& metric, const Eigen::VectorXd& g) {
  if (!metric.identity()) return metric.solve(g);
  return g * (1e-2 / std::max(g.lpNorm<Eigen::Infinity>(), 1e-300));
}

// Curvature pairs (s, y, M⁻¹y, 1/sᵀy) of the preconditioned L-BFGS.
struct Memory {
  std::vector<Eigen::VectorXd> s, y, my;
  std::vector<double> rho;
  void clear() { s.clear(), y.clear(), my.clear(), rho.clear(); }
};

// Preconditioned L-BFGS (two-loop recursion with H₀ = γ M⁻¹, γ = sᵀy / yᵀM⁻¹y of the newest
// pair; Nocedal & Wright Alg. 7.4) with Armijo backtracking; returns the iterations done.
int minimize(const UntangleProblem& problem, const MetricSolver& metric, Eigen::VectorXd& x, double eps,
             int max_iterations, Memory& memory) {
  constexpr int kPairs = 7;
  Eigen::VectorXd g;
  double f = problem.energy(x, eps, &g);
  int iteration = 0;
  for (; iteration < max_iterations; ++iteration) {
    Eigen::VectorXd q = g;
    const int m = static_cast<int>(memory.s.size());
    std::vector<double> alpha(m);
    for (int p = m - 1; p >= 0; --p) {
      alpha[p] = memory.rho[p] * memory.s[p].dot(q);
      q -= alpha[p] * memory.y[p];
    }
    Eigen::VectorXd r = m > 0 ? metric.solve(q) : first_direction(metric, q);
    if (m > 0) r *= memory.s.back().dot(memory.y.back()) / memory.y.back().dot(memory.my.back());
    for (int p = 0; p < m; ++p) {
      const double beta = memory.rho[p] * memory.y[p].dot(r);
      r += (alpha[p] - beta) * memory.s[p];
    }
    Eigen::VectorXd d = -r;
    double slope = g.dot(d);
    if (!(slope < 0.0)) {  // not a descent direction: restart from the preconditioned gradient
      memory.clear();
      d = -first_direction(metric, g);
      slope = g.dot(d);
      if (!(slope < 0.0)) break;
    }
    Eigen::VectorXd x_new, g_new;
    double f_new = f;
    bool accepted = false;
    for (double t = 1.0; t > 1e-9; t *= 0.5) {
      x_new = x + t * d;
      f_new = problem.energy(x_new, eps, &g_new);
      if (f_new <= f + 1e-4 * t * slope) {
        accepted = true;
        break;
      }
    }
    if (!accepted) break;
    Eigen::VectorXd s = x_new - x, y = g_new - g;
    const double sy = s.dot(y);
    if (sy > 1e-12 * s.norm() * y.norm()) {
      if (static_cast<int>(memory.s.size()) == kPairs) {
        memory.s.erase(memory.s.begin());
        memory.y.erase(memory.y.begin());
        memory.my.erase(memory.my.begin());
        memory.rho.erase(memory.rho.begin());
      }
      memory.my.push_back(metric.identity() ? y : metric.solve(y));
      memory.s.push_back(std::move(s));
      memory.y.push_back(std::move(y));
      memory.rho.push_back(1.0 / sy);
    }
    const double decrease = f - f_new;
    x = std::move(x_new);
    g = std::move(g_new);
    f = f_new;
    if (decrease <= 1e-10 * std::abs(f)) {
      ++iteration;
      break;
    }
  }
  return iteration;
}

}  // namespace

int minimize_preconditioned(const UntangleProblem& problem, const Eigen::SparseMatrix<double>& metric, double eps,
                            int max_iterations, Eigen::VectorXd& x) {
  assert(metric.rows() == 0 || 3 * metric.rows() == x.size());
  const MetricSolver solver(metric);
  assert(solver.ok());
  Memory memory;
  return minimize(problem, solver, x, eps, max_iterations, memory);
}

}  // namespace volspline::param
