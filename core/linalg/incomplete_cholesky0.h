// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "core/linalg/csr_matrix.h"

namespace volspline::linalg {

/// Zero fill-in incomplete Cholesky preconditioner M = L Lᵀ ≈ A: L has exactly the pattern of
/// the lower triangle of A (plus the diagonal), no reordering.
///
/// Pivot fallback: if a pivot is ≤ 0 or not finite, the factorization restarts on
/// A + α·S with S = diag(|A_ii|) (1 where A_ii = 0), α = 1e-3 first, then doubled, up to 60
/// times (the Lin–Moré / Eigen IncompleteCholesky strategy without their column scaling). If
/// even that fails (A contains NaN/Inf), M falls back to the identity. shift() reports α.
/// On a matrix without fill (tridiagonal, tree-structured) IC(0) is the exact Cholesky factor.
class IncompleteCholesky0 {
 public:
  /// Factorizes the lower triangle of the square matrix a (the upper triangle is ignored, so
  /// a symmetric matrix may be stored in full).
  void compute(const CsrMatrix& a);

  /// Threads of the next compute() (≥ 1, default 1: none created): with more, consecutive
  /// shifts of the pivot fallback are tried concurrently and the first that succeeds is kept,
  /// so the factor is bit-identical to the one-thread result.
  void set_threads(int threads) { threads_ = threads < 1 ? 1 : threads; }

  /// z = (L Lᵀ)⁻¹ r for n entries (raw arrays, forward then backward substitution); r and z
  /// may alias.
  void solve(const double* r, double* z) const;

  /// solve for k columns at once (r[c] → z[c]), streaming L once for up to 4 of them; each
  /// column's result is bit-identical to solve's. r[c] and z[c] may alias.
  void solve_block(int k, const double* const* r, double* const* z) const;

  /// Returns (L Lᵀ)⁻¹ r; r has n entries.
  Eigen::VectorXd solve(const Eigen::VectorXd& r) const;

  /// Diagonal shift α that was needed (0 when A itself factorized); +Inf if M fell back to I.
  double shift() const { return shift_; }

  /// L with its diagonal, n×n lower triangular (for tests and inspection).
  CsrMatrix factor() const;

  /// Strictly lower part of L, row by row (used by the fused CG kernels).
  const CsrMatrix& strict_lower() const { return lower_; }
  /// Strictly upper part of Lᵀ, row by row, for a gathering backward substitution.
  const CsrMatrix& strict_upper() const { return upper_; }
  /// n entries 1/L_ii.
  const Eigen::VectorXd& inverse_diagonal() const { return inverse_diagonal_; }

 private:
  CsrMatrix lower_;
  CsrMatrix upper_;
  Eigen::VectorXd inverse_diagonal_;
  double shift_ = 0.0;
  int threads_ = 1;
};

}  // namespace volspline::linalg
