// SPDX-License-Identifier: MIT
#include "core/linalg/incomplete_cholesky0.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>

#include "tests/unit/linalg/test_systems.h"

namespace linalg = volspline::linalg;
using linalg::CsrMatrix;
using linalg::Triplet;

namespace {

CsrMatrix tridiagonal(int n) {
  std::vector<Triplet> t;
  for (int i = 0; i < n; ++i) {
    t.push_back({i, i, 2.0 + 0.1 * i});
    if (i > 0) t.push_back({i, i - 1, -1.0 + 0.01 * i});
    if (i + 1 < n) t.push_back({i, i + 1, -1.0 + 0.01 * (i + 1)});
  }
  return CsrMatrix::from_triplets(n, n, t);
}

}  // namespace

TEST_CASE("IC(0) of a tridiagonal matrix is the exact Cholesky factor") {
  const CsrMatrix a = tridiagonal(20);
  linalg::IncompleteCholesky0 ic;
  ic.compute(a);
  CHECK(ic.shift() == 0.0);
  const Eigen::MatrixXd exact = Eigen::LLT<Eigen::MatrixXd>(a.to_dense()).matrixL();
  // Tolerance: both factorizations do the same O(1) operations per entry.
  CHECK((ic.factor().to_dense() - exact).norm() <= 1e-12);
  const Eigen::VectorXd b = linalg::testing::pseudo_random_vector(20, 5);
  const Eigen::VectorXd x = a.to_dense().ldlt().solve(b);
  CHECK((ic.solve(b) - x).norm() <= 1e-12 * x.norm());
}

TEST_CASE("IC(0) reproduces A on its pattern for a 3D grid Laplacian") {
  const CsrMatrix a = linalg::testing::grid_laplacian(4, 3, 5);
  linalg::IncompleteCholesky0 ic;
  ic.compute(a);
  CHECK(ic.shift() == 0.0);
  const Eigen::MatrixXd l = ic.factor().to_dense();
  const Eigen::MatrixXd llt = l * l.transpose();
  double max_error = 0.0;
  for (int i = 0; i < a.rows(); ++i) {
    for (int k = a.row_offsets()[i]; k < a.row_offsets()[i + 1]; ++k) {
      max_error = std::max(max_error, std::abs(llt(i, a.col_indices()[k]) - a.values()[k]));
    }
  }
  CHECK(max_error <= 1e-12);  // (LLᵀ)_ij = A_ij on the pattern is the defining IC(0) property
  CHECK(l.isLowerTriangular(0.0));
  // solve() is the exact inverse of L Lᵀ.
  const Eigen::VectorXd r = linalg::testing::pseudo_random_vector(a.rows(), 8);
  const Eigen::VectorXd z = ic.solve(r);
  CHECK((llt * z - r).norm() <= 1e-12 * r.norm());
  Eigen::VectorXd in_place = r;
  ic.solve(in_place.data(), in_place.data());
  CHECK(in_place == z);
}

TEST_CASE("IC(0) shifts the diagonal when a pivot is not positive") {
  // Symmetric, indefinite: the second pivot 1 − 4 is negative without a shift.
  const CsrMatrix a = CsrMatrix::from_triplets(
      3, 3, {{0, 0, 1.0}, {1, 1, 1.0}, {2, 2, 1.0}, {0, 1, 2.0}, {1, 0, 2.0}});
  linalg::IncompleteCholesky0 ic;
  ic.compute(a);
  CHECK(ic.shift() > 0.0);
  CHECK(std::isfinite(ic.shift()));
  const Eigen::MatrixXd l = ic.factor().to_dense();
  CHECK(l.allFinite());
  CHECK((l.diagonal().array() > 0.0).all());

  // A zero diagonal entry in an otherwise empty row is shifted too.
  const CsrMatrix z = CsrMatrix::from_triplets(2, 2, {{0, 0, 1.0}});
  ic.compute(z);
  CHECK(ic.shift() > 0.0);
}

TEST_CASE("IC(0) falls back to the identity on non-finite values") {
  CsrMatrix a = tridiagonal(4);
  a.values()[0] = std::numeric_limits<double>::quiet_NaN();
  linalg::IncompleteCholesky0 ic;
  ic.compute(a);
  CHECK(std::isinf(ic.shift()));
  const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(4, 1.0, 4.0);
  CHECK(ic.solve(r) == r);
}

TEST_CASE("IC(0) with threads keeps the first shift that works: the same factor bit for bit") {
  // The 3x3 indefinite matrix needs several doublings of the shift; a matrix with NaN fails
  // all 61 attempts and falls back to the identity.
  const CsrMatrix indefinite = CsrMatrix::from_triplets(
      3, 3, {{0, 0, 1.0}, {1, 1, 1.0}, {2, 2, 1.0}, {0, 1, 2.0}, {1, 0, 2.0}});
  CsrMatrix broken = tridiagonal(4);
  broken.values()[0] = std::numeric_limits<double>::quiet_NaN();
  for (const CsrMatrix* a : {&indefinite, static_cast<const CsrMatrix*>(&broken)}) {
    linalg::IncompleteCholesky0 one;
    one.compute(*a);
    for (int threads : {2, 3, 4}) {
      linalg::IncompleteCholesky0 many;
      many.set_threads(threads);
      many.compute(*a);
      CHECK(many.shift() == one.shift());
      CHECK(many.strict_lower().values() == one.strict_lower().values());
      CHECK(many.inverse_diagonal() == one.inverse_diagonal());
    }
  }
}
