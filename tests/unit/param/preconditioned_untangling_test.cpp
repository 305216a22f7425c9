// SPDX-License-Identifier: MIT
#include "core/param/preconditioned_untangling.h"

#include <doctest/doctest.h>

#include <vector>

using namespace volspline;

namespace {

// The path Laplacian of n nodes with both ends tied to fixed nodes: SPD, tridiagonal.
Eigen::SparseMatrix<double> path_laplacian(int n) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 2.0);
    if (i + 1 < n) {
      entries.emplace_back(i, i + 1, -1.0);
      entries.emplace_back(i + 1, i, -1.0);
    }
  }
  Eigen::SparseMatrix<double> m(n, n);
  m.setFromTriplets(entries.begin(), entries.end());
  return m;
}

// E(x) = ½ (x − x*)ᵀ (M ⊗ I₃) (x − x*) for node-major x (x, y, z per node); ε is ignored.
param::UntangleProblem quadratic(const Eigen::SparseMatrix<double>& m, const Eigen::VectorXd& target) {
  param::UntangleProblem problem;
  problem.energy = [m, target](const Eigen::VectorXd& x, double, Eigen::VectorXd* gradient) {
    const Eigen::Index n = m.rows();
    Eigen::MatrixXd d(n, 3), md(n, 3);
    for (Eigen::Index v = 0; v < n; ++v) d.row(v) = (x - target).segment<3>(3 * v).transpose();
    md = m * d;
    if (gradient) {
      gradient->resize(3 * n);
      for (Eigen::Index v = 0; v < n; ++v) gradient->segment<3>(3 * v) = md.row(v).transpose();
    }
    return 0.5 * (d.array() * md.array()).sum();
  };
  problem.min_det = [](const Eigen::VectorXd&) { return 1.0; };
  return problem;
}

}  // namespace

TEST_CASE("L-BFGS preconditioned by the exact Hessian of a quadratic takes one Newton step") {
  const int n = 40;
  const Eigen::SparseMatrix<double> m = path_laplacian(n);
  Eigen::VectorXd target(3 * n), x = Eigen::VectorXd::Zero(3 * n);
  for (int i = 0; i < 3 * n; ++i) target(i) = std::sin(0.37 * i);
  // M⁻¹∇E = x − x* exactly, so the first step with t = 1 lands on x*; tolerance from the
  // Cholesky solve's rounding.
  CHECK(param::minimize_preconditioned(quadratic(m, target), m, 1e-3, 1, x) == 1);
  CHECK((x - target).lpNorm<Eigen::Infinity>() < 1e-10);
}

TEST_CASE("without a metric the same quadratic needs many more L-BFGS iterations but converges") {
  const int n = 40;
  const Eigen::SparseMatrix<double> m = path_laplacian(n);
  Eigen::VectorXd target(3 * n), x = Eigen::VectorXd::Zero(3 * n);
  for (int i = 0; i < 3 * n; ++i) target(i) = std::sin(0.37 * i);
  const int iterations = param::minimize_preconditioned(quadratic(m, target), Eigen::SparseMatrix<double>(), 1e-3, 2000, x);
  CHECK(iterations > 10);
  // Stops on a relative energy decrease of 1e-10, so x is close to x*, not exact: E(x) ≈
  // ½ λ_min |x − x*|² with λ_min ≈ (π/41)² bounds the error loosely.
  CHECK((x - target).lpNorm<Eigen::Infinity>() < 1e-3);
}
