// SPDX-License-Identifier: MIT
#pragma once

#include "core/linalg/csr_matrix.h"
#include "core/linalg/incomplete_cholesky0.h"

namespace volspline::spline {

/// CG preconditioner for B-spline Gram (mass) matrices: IC(0) of A after dropping the weak
/// couplings |a_ij| < drop·sqrt(a_ii a_jj). A cubic B-spline couples 7³ = 343 neighbours, but
/// the couplings at distance ≥ 2 along two axes are below 1 % of the diagonal, so about 81 per
/// row remain and the factorization stays cheap, while it still removes the ~κ(1D)³ condition
/// number that makes Jacobi-preconditioned CG slow on trivariate Gram matrices.
/// compute/solve as linalg::IncompleteCholesky0 (the solver concept of STYLE.md).
class SparsifiedCholesky {
 public:
  /// Drop threshold relative to the geometric mean of the two diagonal entries, in [0, 1).
  explicit SparsifiedCholesky(double drop = 0.01) : drop_(drop) {}
  /// Factorizes the kept entries of the square symmetric matrix a. Reads only the diagonal and
  /// the upper triangle, so a may be stored in full or as its upper triangle (as CG reads it).
  void compute(const linalg::CsrMatrix& a);
  /// Threads of the next compute (see IncompleteCholesky0::set_threads; same factor for any count).
  void set_threads(int threads) { ic_.set_threads(threads); }
  /// z = M⁻¹ r for n = a.rows() entries; r and z may alias.
  void solve(const double* r, double* z) const { ic_.solve(r, z); }
  /// solve for k columns at once (r[c] → z[c]; see IncompleteCholesky0::solve_block).
  void solve_block(int k, const double* const* r, double* const* z) const { ic_.solve_block(k, r, z); }

 private:
  double drop_;
  linalg::IncompleteCholesky0 ic_;
};

}  // namespace volspline::spline
