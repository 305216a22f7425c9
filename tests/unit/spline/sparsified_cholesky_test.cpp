// SPDX-License-Identifier: MIT
#include "core/spline/sparsified_cholesky.h"

#include <doctest/doctest.h>

#include "core/linalg/triplet.h"

using namespace volspline;

TEST_CASE("sparsified Cholesky with no dropped entry is exact on a tridiagonal matrix") {
  std::vector<linalg::Triplet> t;
  const int n = 5;
  for (int i = 0; i < n; ++i) {
    t.push_back({i, i, 4.0});
    if (i + 1 < n) {
      t.push_back({i, i + 1, -1.0});
      t.push_back({i + 1, i, -1.0});
    }
  }
  const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(n, n, t);
  spline::SparsifiedCholesky m(0.01);
  m.compute(a);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  Eigen::VectorXd x(n);
  m.solve(b.data(), x.data());
  CHECK((a * x - b).norm() < 1e-12);  // IC(0) of a tridiagonal matrix is its Cholesky factor
}

TEST_CASE("sparsified Cholesky drops weak couplings") {
  std::vector<linalg::Triplet> t = {{0, 0, 1.0}, {1, 1, 1.0}, {0, 1, 1e-4}, {1, 0, 1e-4}};
  const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(2, 2, t);
  spline::SparsifiedCholesky m(0.01);
  m.compute(a);
  const double r[2] = {1.0, 2.0};
  double z[2];
  m.solve(r, z);
  CHECK(z[0] == doctest::Approx(1.0).epsilon(1e-14));  // diagonal only
  CHECK(z[1] == doctest::Approx(2.0).epsilon(1e-14));
}

TEST_CASE("sparsified Cholesky reads only the upper triangle") {
  // A symmetric 4x4 SPD matrix stored in full and as its upper triangle give the same M⁻¹.
  const double full[4][4] = {{4, 1, 0.5, 0}, {1, 5, 1, 0.2}, {0.5, 1, 6, 1}, {0, 0.2, 1, 3}};
  std::vector<linalg::Triplet> all, upper;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (full[i][j] != 0.0) {
        all.push_back({i, j, full[i][j]});
        if (j >= i) upper.push_back({i, j, full[i][j]});
      }
  spline::SparsifiedCholesky a(0.01), b(0.01);
  a.compute(linalg::CsrMatrix::from_triplets(4, 4, all));
  b.compute(linalg::CsrMatrix::from_triplets(4, 4, upper));
  const double r[4] = {1.0, -2.0, 0.5, 3.0};
  double za[4], zb[4];
  a.solve(r, za);
  b.solve(r, zb);
  for (int i = 0; i < 4; ++i) CHECK(za[i] == doctest::Approx(zb[i]).epsilon(1e-15));
}
