// SPDX-License-Identifier: MIT
#include "core/linalg/algebraic_multigrid.h"

#include <doctest/doctest.h>

#include <vector>

#include <Eigen/Dense>

#include "core/linalg/conjugate_gradient.h"
#include "tests/unit/linalg/test_systems.h"

namespace linalg = volspline::linalg;
using linalg::AlgebraicMultigrid;
using linalg::CsrMatrix;
using linalg::Triplet;

namespace {

// 5-point Laplacian of an n×n interior grid with Dirichlet boundary (the Tutte map's matrix on
// a regular grid), edge weights 1 + 0.5·sin(i + 2j) so that the couplings vary.
CsrMatrix varying_grid_laplacian(int n) {
  const auto id = [n](int i, int j) { return j * n + i; };
  const auto weight = [](int i, int j) { return 1.0 + 0.5 * std::sin(double(i + 2 * j)); };
  std::vector<Triplet> t;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = id(i, j);
      double diagonal = 0.0;
      const int di[4] = {-1, 1, 0, 0}, dj[4] = {0, 0, -1, 1};
      for (int q = 0; q < 4; ++q) {
        const int a = i + di[q], b = j + dj[q];
        // The edge's weight from its lower end, so that the matrix is symmetric.
        const double w = weight(std::min(i, a), std::min(j, b)) + (q < 2 ? 0.0 : 0.25);
        diagonal += w;
        if (a >= 0 && a < n && b >= 0 && b < n) t.push_back({v, id(a, b), -w});
      }
      t.push_back({v, v, diagonal});
    }
  return CsrMatrix::from_triplets(n * n, n * n, t);
}

int amg_cg_iterations(const CsrMatrix& a, Eigen::VectorXd* solution = nullptr) {
  linalg::ConjugateGradient<AlgebraicMultigrid> cg;
  cg.set_tolerance(1e-10);
  cg.compute(a);
  const Eigen::VectorXd b = linalg::testing::pseudo_random_vector(a.rows(), 3);
  const Eigen::VectorXd x = cg.solve(b);
  CHECK(cg.info() == linalg::SolverInfo::Success);
  if (solution) *solution = x;
  return cg.iterations();
}

}  // namespace

TEST_CASE("AMG of a matrix at most kCoarseSize is its exact inverse") {
  const CsrMatrix a = varying_grid_laplacian(12);  // 144 unknowns
  AlgebraicMultigrid amg;
  amg.compute(a);
  CHECK(amg.num_levels() == 1);
  const Eigen::VectorXd b = linalg::testing::pseudo_random_vector(a.rows(), 1);
  const Eigen::VectorXd x = a.to_dense().ldlt().solve(b);
  // Tolerance: both are dense LDLᵀ solves of a well-conditioned 144×144 system.
  CHECK((amg.solve(b) - x).norm() <= 1e-12 * x.norm());
}

TEST_CASE("AMG-preconditioned CG needs about as many iterations on a 16× finer grid") {
  const CsrMatrix coarse = varying_grid_laplacian(48);
  const CsrMatrix fine = varying_grid_laplacian(192);
  AlgebraicMultigrid amg;
  amg.compute(fine);
  CHECK(amg.num_levels() >= 3);
  CHECK(amg.level_size(1) < fine.rows() / 4);
  CHECK(amg.operator_complexity() < 2.0);
  Eigen::VectorXd x;
  const int coarse_iterations = amg_cg_iterations(coarse);
  const int fine_iterations = amg_cg_iterations(fine, &x);
  // IC(0) needs √16 = 4× the iterations here; multigrid stays within a few.
  CHECK(fine_iterations <= 30);
  CHECK(fine_iterations <= coarse_iterations + 6);
  linalg::ConjugateGradient<linalg::IncompleteCholesky0> reference(fine);
  reference.set_tolerance(1e-12);
  const Eigen::VectorXd y = reference.solve(linalg::testing::pseudo_random_vector(fine.rows(), 3));
  CHECK(reference.iterations() > 2 * fine_iterations);
  // Tolerance: both solves stop at relative residual ≤ 1e-10, the condition number is ~1e4.
  CHECK((x - y).norm() <= 1e-5 * y.norm());
}

TEST_CASE("AMG's V-cycle is a symmetric positive definite operator") {
  const CsrMatrix a = varying_grid_laplacian(40);
  AlgebraicMultigrid amg;
  amg.compute(a);
  REQUIRE(amg.num_levels() >= 2);
  const Eigen::VectorXd u = linalg::testing::pseudo_random_vector(a.rows(), 7);
  const Eigen::VectorXd v = linalg::testing::pseudo_random_vector(a.rows(), 8);
  const double uv = u.dot(amg.solve(v)), vu = v.dot(amg.solve(u));
  // Tolerance: the two products round differently, both of size ~|u||v|/λ_min.
  CHECK(std::abs(uv - vu) <= 1e-12 * u.norm() * amg.solve(v).norm());
  CHECK(u.dot(amg.solve(u)) > 0.0);
  CHECK(v.dot(amg.solve(v)) > 0.0);
}

TEST_CASE("AMG block solves are bit-identical to single solves, also in place") {
  const CsrMatrix a = varying_grid_laplacian(30);
  AlgebraicMultigrid amg;
  amg.compute(a);
  std::vector<Eigen::VectorXd> r, z(5);
  for (int c = 0; c < 5; ++c) r.push_back(linalg::testing::pseudo_random_vector(a.rows(), 20 + c));
  const double* rp[5];
  double* zp[5];
  for (int c = 0; c < 5; ++c) {
    z[c].resize(a.rows());
    rp[c] = r[c].data();
    zp[c] = z[c].data();
  }
  amg.solve_block(5, rp, zp);
  for (int c = 0; c < 5; ++c) {
    CHECK(z[c] == amg.solve(r[c]));
    Eigen::VectorXd in_place = r[c];
    amg.solve(in_place.data(), in_place.data());
    CHECK(in_place == z[c]);
  }
}

TEST_CASE("AMG of a cotan Laplacian plus mass agrees with a dense solve") {
  const auto [v, f] = linalg::testing::icosphere(4);  // 2562 vertices
  const CsrMatrix a = linalg::testing::cotan_laplacian_plus_mass(v, f, 0.1);
  Eigen::VectorXd x;
  CHECK(amg_cg_iterations(a, &x) <= 30);
  const Eigen::VectorXd exact = a.to_dense().ldlt().solve(linalg::testing::pseudo_random_vector(a.rows(), 3));
  // Tolerance: relative residual 1e-10 times the condition number (~1e3).
  CHECK((x - exact).norm() <= 1e-6 * exact.norm());
}

TEST_CASE("AMG without strong couplings ends in Gauss-Seidel sweeps") {
  // A large diagonal matrix: no aggregates, too large for a dense level; symmetric
  // Gauss–Seidel is then its exact inverse.
  const int n = 3000;
  std::vector<Triplet> t;
  for (int i = 0; i < n; ++i) t.push_back({i, i, 1.0 + i % 7});
  const CsrMatrix a = CsrMatrix::from_triplets(n, n, t);
  AlgebraicMultigrid amg;
  amg.compute(a);
  CHECK(amg.num_levels() == 2);
  CHECK(amg.level_size(1) == 0);
  const Eigen::VectorXd b = linalg::testing::pseudo_random_vector(n, 4);
  const Eigen::VectorXd z = amg.solve(b);
  double error = 0.0;
  for (int i = 0; i < n; ++i) error = std::max(error, std::abs(z[i] * (1.0 + i % 7) - b[i]));
  CHECK(error <= 1e-15);
}
