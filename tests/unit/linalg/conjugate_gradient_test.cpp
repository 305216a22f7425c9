// SPDX-License-Identifier: MIT
#include "core/linalg/conjugate_gradient.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/IterativeLinearSolvers>

#include "tests/unit/linalg/test_systems.h"

namespace linalg = volspline::linalg;
using linalg::ConjugateGradient;
using linalg::CsrMatrix;
using linalg::SolverInfo;

namespace {

// A preconditioner known only through the generic compute/solve interface (no fused path).
class GenericJacobi {
 public:
  void compute(const CsrMatrix& a) { inner_.compute(a); }
  void solve(const double* r, double* z) const { inner_.solve(r, z); }

 private:
  linalg::JacobiPreconditioner inner_;
};

// IC(0) known only through the generic interface, with the optional block solve.
class GenericBlockCholesky {
 public:
  void compute(const CsrMatrix& a) { inner_.compute(a); }
  void solve(const double* r, double* z) const { inner_.solve(r, z); }
  void solve_block(int k, const double* const* r, double* const* z) const {
    inner_.solve_block(k, r, z);
  }

 private:
  linalg::IncompleteCholesky0 inner_;
};

struct TestSystem {
  const char* name;
  CsrMatrix a;
};

std::vector<TestSystem> laplacian_systems() {
  const auto sphere = linalg::testing::icosphere(3);  // 642 vertices
  return {{"grid 7x6x5", linalg::testing::grid_laplacian(7, 6, 5)},
          {"icosphere cotan + mass", linalg::testing::cotan_laplacian_plus_mass(
                                         sphere.first, sphere.second, 1e-2)}};
}

// Eigen's counterpart of each of our preconditioners (IC: dense Cholesky is not a
// preconditioner Eigen offers with natural ordering and zero fill, so compare to Jacobi there).
template <class P>
Eigen::VectorXd eigen_cg(const CsrMatrix& a, const Eigen::VectorXd& b, double tol) {
  const Eigen::SparseMatrix<double> e = a.to_eigen();
  if constexpr (std::is_same_v<P, linalg::IdentityPreconditioner>) {
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
                             Eigen::IdentityPreconditioner>
        cg(e);
    cg.setTolerance(tol);
    return cg.solve(b);
  } else {
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg(e);
    cg.setTolerance(tol);
    return cg.solve(b);
  }
}

}  // namespace

TEST_CASE("2x2 system by hand") {
  // [4 1; 1 3] x = [1; 2] has x = [1/11; 7/11]; CG is exact after n = 2 steps.
  const CsrMatrix a =
      CsrMatrix::from_triplets(2, 2, {{0, 0, 4.0}, {0, 1, 1.0}, {1, 0, 1.0}, {1, 1, 3.0}});
  ConjugateGradient<linalg::IdentityPreconditioner> cg(a);
  const Eigen::VectorXd x = cg.solve(Eigen::Vector2d(1.0, 2.0));
  CHECK(cg.info() == SolverInfo::Success);
  CHECK(cg.iterations() <= 2);
  CHECK(cg.residual() <= 1e-10);
  // Tolerance: two CG steps on a well-conditioned 2×2 system round to a few ulps.
  CHECK(x[0] == doctest::Approx(1.0 / 11.0).epsilon(1e-14));
  CHECK(x[1] == doctest::Approx(7.0 / 11.0).epsilon(1e-14));
}

TEST_CASE_TEMPLATE("CG agrees with a dense direct solve and with Eigen's CG", P,
                   linalg::IdentityPreconditioner, linalg::JacobiPreconditioner,
                   linalg::IncompleteCholesky0, GenericJacobi) {
  for (const TestSystem& s : laplacian_systems()) {
    CAPTURE(s.name);
    const int n = s.a.rows();
    const Eigen::VectorXd b = linalg::testing::pseudo_random_vector(n, 42);
    ConjugateGradient<P> cg;
    cg.set_tolerance(1e-12);
    cg.compute(s.a);
    const Eigen::VectorXd x = cg.solve(b);
    CHECK(cg.info() == SolverInfo::Success);
    CHECK(cg.iterations() > 0);
    CHECK(cg.residual() <= 1e-12);
    // The reported residual is the true one.
    CHECK(cg.residual() == doctest::Approx((b - s.a * x).norm() / b.norm()).epsilon(1e-6));
    // Tolerance: relative residual 1e-12 times the condition number (< 1e3 here) is < 1e-9.
    const Eigen::VectorXd direct = s.a.to_dense().ldlt().solve(b);
    CHECK((x - direct).norm() <= 1e-8 * direct.norm());
    const Eigen::VectorXd reference = eigen_cg<P>(s.a, b, 1e-12);
    CHECK((x - reference).norm() <= 1e-8 * reference.norm());

    // Deterministic: a second solve gives the same bytes.
    const Eigen::VectorXd again = cg.solve(b);
    CHECK(again == x);
  }
}

TEST_CASE_TEMPLATE("warm start from the solution takes no iteration", P,
                   linalg::IdentityPreconditioner, linalg::JacobiPreconditioner,
                   linalg::IncompleteCholesky0) {
  const CsrMatrix a = linalg::testing::grid_laplacian(5, 5, 5);
  const Eigen::VectorXd b = linalg::testing::pseudo_random_vector(a.rows(), 1);
  ConjugateGradient<P> cg(a);
  const Eigen::VectorXd x = cg.solve(b);
  REQUIRE(cg.info() == SolverInfo::Success);
  const Eigen::VectorXd x2 = cg.solve(b, x);
  CHECK(cg.info() == SolverInfo::Success);
  CHECK(cg.iterations() == 0);
  CHECK(x2 == x);

  // A nearby guess needs fewer iterations than a cold start.
  const int cold = [&] {
    cg.solve(b);
    return cg.iterations();
  }();
  cg.solve(b, x + 1e-6 * Eigen::VectorXd::Ones(a.rows()));
  CHECK(cg.info() == SolverInfo::Success);
  CHECK(cg.iterations() < cold);
}

TEST_CASE("iteration counts match Eigen's (which counts one less)") {
  const CsrMatrix a = linalg::testing::grid_laplacian(8, 8, 8);
  const Eigen::VectorXd b = linalg::testing::pseudo_random_vector(a.rows(), 9);
  ConjugateGradient<linalg::JacobiPreconditioner> cg(a);
  cg.solve(b);
  const Eigen::SparseMatrix<double> e = a.to_eigen();  // Eigen keeps a reference to it
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> eigen(e);
  eigen.setTolerance(1e-10);
  const Eigen::VectorXd x_eigen = eigen.solve(b);  // the solve runs on assignment
  // Same algorithm and stopping rule; rounding may move the stop by one step.
  CHECK(std::abs(cg.iterations() - (static_cast<int>(eigen.iterations()) + 1)) <= 1);
}

TEST_CASE("max_iterations reached gives NotConverged") {
  const CsrMatrix a = linalg::testing::grid_laplacian(6, 6, 6);
  const Eigen::VectorXd b = linalg::testing::pseudo_random_vector(a.rows(), 2);
  ConjugateGradient<linalg::JacobiPreconditioner> cg(a);
  CHECK(cg.max_iterations() == 2 * a.rows());
  cg.set_max_iterations(3);
  const Eigen::VectorXd x = cg.solve(b);
  CHECK(cg.info() == SolverInfo::NotConverged);
  CHECK(cg.iterations() == 3);
  CHECK(cg.residual() > 1e-10);
  CHECK(cg.residual() < 1.0);
  CHECK(cg.residual() == doctest::Approx((b - a * x).norm() / b.norm()).epsilon(1e-9));

  cg.set_max_iterations(0);
  cg.solve(b);
  CHECK(cg.info() == SolverInfo::NotConverged);
  CHECK(cg.iterations() == 0);
  CHECK(cg.residual() == doctest::Approx(1.0));
}

TEST_CASE_TEMPLATE("non-SPD matrices report a problem instead of crashing", P,
                   linalg::IdentityPreconditioner, linalg::JacobiPreconditioner,
                   linalg::IncompleteCholesky0) {
  // Symmetric indefinite: diag(2, -1, 3, -4) plus a coupling.
  const CsrMatrix a = CsrMatrix::from_triplets(
      4, 4, {{0, 0, 2.0}, {1, 1, -1.0}, {2, 2, 3.0}, {3, 3, -4.0}, {0, 1, 0.5}, {1, 0, 0.5}});
  ConjugateGradient<P> cg(a);
  cg.solve(Eigen::Vector4d(1.0, 1.0, 1.0, 1.0));
  CHECK(cg.info() != SolverInfo::Success);
  // Negative definite: pᵀAp < 0 at the first step.
  const CsrMatrix neg = CsrMatrix::from_triplets(2, 2, {{0, 0, -1.0}, {1, 1, -2.0}});
  ConjugateGradient<P> cg2(neg);
  const Eigen::VectorXd x = cg2.solve(Eigen::Vector2d(1.0, 1.0));
  CHECK(cg2.info() != SolverInfo::Success);
  CHECK(x.size() == 2);
}

TEST_CASE("zero and non-finite right-hand sides") {
  const CsrMatrix a = linalg::testing::grid_laplacian(3, 3, 3);
  ConjugateGradient<linalg::JacobiPreconditioner> cg(a);
  const Eigen::VectorXd x = cg.solve(Eigen::VectorXd::Zero(27), Eigen::VectorXd::Ones(27));
  CHECK(cg.info() == SolverInfo::Success);
  CHECK(cg.iterations() == 0);
  CHECK(cg.residual() == 0.0);
  CHECK(x.isZero(0.0));

  Eigen::VectorXd b = Eigen::VectorXd::Ones(27);
  b[4] = std::numeric_limits<double>::quiet_NaN();
  cg.solve(b);
  CHECK(cg.info() == SolverInfo::NumericalIssue);
}

TEST_CASE("several right-hand sides are solved column by column") {
  const auto sphere = linalg::testing::icosphere(2);
  const CsrMatrix a =
      linalg::testing::cotan_laplacian_plus_mass(sphere.first, sphere.second, 1e-1);
  const int n = a.rows();
  Eigen::MatrixXd b(n, 3);
  for (int c = 0; c < 3; ++c) b.col(c) = linalg::testing::pseudo_random_vector(n, 100 + c);
  b.col(1).setZero();
  ConjugateGradient<linalg::IncompleteCholesky0> cg(a);
  const Eigen::MatrixXd x = cg.solve(b);
  CHECK(x.rows() == n);
  CHECK(x.cols() == 3);
  CHECK(cg.info() == SolverInfo::Success);
  int max_iterations = 0;
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd xc = cg.solve(Eigen::VectorXd(b.col(c)));
    CHECK(xc == x.col(c));
    max_iterations = std::max(max_iterations, cg.iterations());
  }
  cg.solve(b);
  CHECK(cg.iterations() == max_iterations);

  const Eigen::MatrixXd warm = cg.solve(b, x);
  CHECK(cg.iterations() == 0);
  CHECK(warm == x);
}

TEST_CASE_TEMPLATE("a block solve gives each column exactly its lone solve", P,
                   linalg::IdentityPreconditioner, linalg::JacobiPreconditioner,
                   linalg::IncompleteCholesky0, GenericJacobi, GenericBlockCholesky) {
  const auto sphere = linalg::testing::icosphere(2);
  const CsrMatrix a =
      linalg::testing::cotan_laplacian_plus_mass(sphere.first, sphere.second, 1e-2);
  const int n = a.rows();
  // 7 columns: more than one block of 4; one zero column, one scaled copy (converges at the
  // same step), one with a warm start at its solution (no iteration).
  Eigen::MatrixXd b(n, 7);
  for (int c = 0; c < 7; ++c) b.col(c) = linalg::testing::pseudo_random_vector(n, 300 + c);
  b.col(2).setZero();
  b.col(5) = 1e3 * b.col(0);
  ConjugateGradient<P> cg(a);
  cg.set_tolerance(1e-9);
  const Eigen::VectorXd solution6 = cg.solve(Eigen::VectorXd(b.col(6)));
  Eigen::MatrixXd x0 = Eigen::MatrixXd::Zero(n, 7);
  x0.col(6) = solution6;
  x0.col(3) = linalg::testing::pseudo_random_vector(n, 999);
  for (int cap : {-1, 7}) {  // converged, and stopped by the iteration cap
    cg.set_max_iterations(cap);
    const Eigen::MatrixXd x = cg.solve(b, x0);
    const linalg::SolverInfo block_info = cg.info();
    const int block_iterations = cg.iterations();
    const double block_residual = cg.residual();
    int worst = 0, most = 0;
    double largest = 0.0;
    for (int c = 0; c < 7; ++c) {
      const Eigen::VectorXd xc = cg.solve(Eigen::VectorXd(b.col(c)), Eigen::VectorXd(x0.col(c)));
      CHECK(xc == x.col(c));
      worst = std::max(worst, static_cast<int>(cg.info()));
      most = std::max(most, cg.iterations());
      largest = std::max(largest, cg.residual());
    }
    CHECK(static_cast<int>(block_info) == worst);
    CHECK(block_iterations == most);
    CHECK(block_residual == largest);
    if (cap > 0) CHECK(block_info == SolverInfo::NotConverged);
    if (cap < 0) CHECK(block_info == SolverInfo::Success);
  }
}

TEST_CASE("a non-finite column fails alone in a block solve") {
  const CsrMatrix a = linalg::testing::grid_laplacian(5, 4, 3);
  const int n = a.rows();
  Eigen::MatrixXd b(n, 2);
  b.col(0) = linalg::testing::pseudo_random_vector(n, 7);
  b.col(1) = b.col(0);
  b(3, 1) = std::numeric_limits<double>::quiet_NaN();
  ConjugateGradient<linalg::IncompleteCholesky0> cg(a);
  const Eigen::MatrixXd x = cg.solve(b);
  CHECK(cg.info() == SolverInfo::NumericalIssue);
  const Eigen::VectorXd x0 = cg.solve(Eigen::VectorXd(b.col(0)));
  CHECK(cg.info() == SolverInfo::Success);
  CHECK(x0 == x.col(0));
}

TEST_CASE("compute copies what it needs: the matrix may go away") {
  ConjugateGradient<linalg::IncompleteCholesky0> cg;
  Eigen::VectorXd expected;
  {
    const CsrMatrix a = linalg::testing::grid_laplacian(4, 4, 4);
    cg.compute(a);
    expected = a.to_dense().ldlt().solve(Eigen::VectorXd::Ones(64));
  }
  CHECK(cg.size() == 64);
  const Eigen::VectorXd x = cg.solve(Eigen::VectorXd::Ones(64));
  CHECK(cg.info() == SolverInfo::Success);
  // Tolerance: residual 1e-10 times a condition number below 10.
  CHECK((x - expected).norm() <= 1e-9 * expected.norm());
}

TEST_CASE_TEMPLATE("threaded matrix products give bit-identical solves", P,
                   linalg::IdentityPreconditioner, linalg::JacobiPreconditioner,
                   linalg::IncompleteCholesky0) {
  // 1,848 unknowns: a product in one part (too few entries to cut), the IC(0) factorization
  // concurrent; 1, 3 and 4 columns. The parted product has its own case below.
  const CsrMatrix a = linalg::testing::grid_laplacian(14, 12, 11);
  const int n = a.rows();
  Eigen::MatrixXd b(n, 4);
  for (int c = 0; c < 4; ++c) b.col(c) = linalg::testing::pseudo_random_vector(n, 40 + c);
  ConjugateGradient<P> one;
  one.set_tolerance(1e-10).compute(a);
  for (int threads : {2, 3}) {
    ConjugateGradient<P> many;
    many.set_tolerance(1e-10).set_threads(threads).compute(a);
    for (int k : {1, 3, 4}) {
      const Eigen::MatrixXd x1 = one.solve(b.leftCols(k));
      const Eigen::MatrixXd xt = many.solve(b.leftCols(k));
      CHECK(x1 == xt);  // exact: the same operations in the same order
      CHECK(one.iterations() == many.iterations());
      CHECK(one.residual() == many.residual());
    }
  }
}

TEST_CASE("a large product is cut into parts: the exact product within rounding, the same bits for every thread count") {
  // Banded SPD matrix with 2,400 rows and 60 upper diagonals: 141,570 strict-upper entries,
  // above detail::kMinPartedSpmvNnz, so the products run in detail::kSpmvParts parts.
  const int n = 2400, band = 60;
  std::vector<linalg::Triplet> triplets;
  for (int i = 0; i < n; ++i) {
    double off_sum = 0.0;
    for (int j = std::max(0, i - band); j <= std::min(n - 1, i + band); ++j) {
      if (j == i) continue;
      const double v = -1.0 / (1.0 + std::abs(i - j) + 0.001 * ((i + j) % 7));
      triplets.push_back({i, j, v});
      off_sum += std::abs(v);
    }
    triplets.push_back({i, i, off_sum + 1.0});
  }
  const CsrMatrix a = CsrMatrix::from_triplets(n, n, triplets);
  const linalg::detail::SymmetricMatrix one = linalg::detail::symmetric_from_upper(a, 1);
  REQUIRE(one.strict_upper.nnz() >= linalg::detail::kMinPartedSpmvNnz);
  REQUIRE(static_cast<int>(one.part_rows.size()) == linalg::detail::kSpmvParts + 1);
  const Eigen::VectorXd p = linalg::testing::pseudo_random_vector(n, 7);
  const Eigen::VectorXd expected = a * p;
  Eigen::VectorXd q1 = Eigen::VectorXd::Zero(n);
  const double pq1 = linalg::detail::symmetric_spmv(one, p.data(), q1.data());
  // Tolerance: sums of 121 terms of size <= 4 in another order, rounding ~1e-13 relative.
  CHECK((q1 - expected).norm() <= 1e-12 * expected.norm());
  CHECK(std::abs(pq1 - p.dot(expected)) <= 1e-12 * std::abs(p.dot(expected)));
  for (int threads : {2, 3, 4}) {
    const linalg::detail::SymmetricMatrix many = linalg::detail::symmetric_from_upper(a, threads);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(n);
    const double pq = linalg::detail::symmetric_spmv(many, p.data(), q.data());
    CHECK(q == q1);  // exact: the parts are summed in part order whatever the threads
    CHECK(pq == pq1);
  }
  Eigen::MatrixXd b(n, 3);
  for (int c = 0; c < 3; ++c) b.col(c) = linalg::testing::pseudo_random_vector(n, 50 + c);
  ConjugateGradient<linalg::IncompleteCholesky0> cg1;
  cg1.set_tolerance(1e-10).compute(a);
  const Eigen::MatrixXd x1 = cg1.solve(b);
  CHECK(cg1.info() == SolverInfo::Success);
  const Eigen::MatrixXd dense_x = a.to_dense().llt().solve(b);
  // Tolerance: residual 1e-10 and a diagonally dominant matrix (condition number ~ 200).
  CHECK((x1 - dense_x).norm() <= 1e-7 * dense_x.norm());
  ConjugateGradient<linalg::IncompleteCholesky0> cg2;
  cg2.set_tolerance(1e-10).set_threads(2).compute(a);
  CHECK(cg2.solve(b) == x1);
  CHECK(cg2.iterations() == cg1.iterations());
}
