// SPDX-License-Identifier: MIT
#include "core/spline/component_solve.h"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include <Eigen/Cholesky>

#include "core/linalg/triplet.h"
#include "tests/unit/spline/identity_test_volume.h"

using namespace volspline;

namespace {

// The upper triangle (diagonal included) of a dense symmetric matrix as CSR.
linalg::CsrMatrix upper_csr(const Eigen::MatrixXd& a) {
  std::vector<linalg::Triplet> entries;
  for (int i = 0; i < a.rows(); ++i)
    for (int j = i; j < a.cols(); ++j)
      if (a(i, j) != 0.0) entries.push_back({i, j, a(i, j)});
  return linalg::CsrMatrix::from_triplets(static_cast<int>(a.rows()), static_cast<int>(a.cols()), entries);
}

}  // namespace

TEST_CASE("solve_normal_equations: a 2×2 system by hand, from its upper triangle") {
  // [4 1; 1 3] x = [1 2; 5 -1]: x = [1/11 7/11; 16/11 -9/11] (Cramer, det 11).
  Eigen::MatrixXd gram(2, 2);
  gram << 4, 1, 1, 3;
  Eigen::MatrixXd rhs(2, 2);
  rhs << 1, 5, 2, -1;
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(2, 2);
  const spline::ComponentSolveResult r = spline::solve_normal_equations(upper_csr(gram), rhs, x, 1e-14, 100);
  CHECK(r.converged);
  CHECK(r.cg_iterations <= 4);  // CG is exact in n steps per column (plus the restart check)
  Eigen::MatrixXd expected(2, 2);
  expected << 1.0 / 11, 16.0 / 11, 7.0 / 11, -9.0 / 11;
  CHECK((x - expected).norm() < 1e-13);
}

TEST_CASE("solve_normal_equations agrees with a dense solve and does not depend on the thread count") {
  const int n = 40;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {  // a banded SPD matrix: 1D Laplacian plus a shift
    a(i, i) = 2.5;
    if (i + 1 < n) a(i, i + 1) = a(i + 1, i) = -1.0;
    if (i + 3 < n) a(i, i + 3) = a(i + 3, i) = 0.2;
  }
  Eigen::MatrixXd rhs(n, 3);
  for (int i = 0; i < n; ++i) rhs.row(i) << std::sin(0.3 * i), 1.0, i % 7 - 3.0;
  const Eigen::MatrixXd dense = a.ldlt().solve(rhs);
  Eigen::MatrixXd x1 = Eigen::MatrixXd::Zero(n, 3), x3 = x1;
  CHECK(spline::solve_normal_equations(upper_csr(a), rhs, x1, 1e-12, 500, 1).converged);
  CHECK(spline::solve_normal_equations(upper_csr(a), rhs, x3, 1e-12, 500, 3).converged);
  // Iterative: within the relative residual times the condition number (≈ 10 here).
  CHECK((x1 - dense).norm() < 1e-9 * dense.norm());
  CHECK(x1 == x3);
}

TEST_CASE("solve_components writes each solution column into its own component") {
  // Gram = identity: the solution is the right-hand side, written into components 2 and 0;
  // component 1 keeps its values.
  spline::TSpline ts = test::identity_test_volume();
  const int n = ts.num_functions();
  const Eigen::MatrixXd before = ts.points();
  Eigen::MatrixXd rhs(n, 2);
  for (int i = 0; i < n; ++i) rhs.row(i) << 0.5 * i, -1.0 - i;
  const spline::ComponentSolveResult r =
      spline::solve_components(ts, upper_csr(Eigen::MatrixXd::Identity(n, n)), rhs, {2, 0}, 1e-12, 10);
  CHECK(r.converged);
  CHECK((ts.points().col(2) - rhs.col(0)).norm() < 1e-12);
  CHECK((ts.points().col(0) - rhs.col(1)).norm() < 1e-12);
  CHECK(ts.points().col(1) == before.col(1));
}
