// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "core/linalg/csr_matrix.h"

namespace volspline::linalg {

/// Diagonal (Jacobi) preconditioner M = diag(A), as Eigen's DiagonalPreconditioner: a zero or
/// missing diagonal entry is replaced by 1 so that M stays invertible.
class JacobiPreconditioner {
 public:
  /// Stores 1/A_ii for the square matrix a.
  void compute(const CsrMatrix& a);

  /// z = M⁻¹ r for n = a.rows() entries (raw arrays); r and z may alias.
  void solve(const double* r, double* z) const;

  /// Returns M⁻¹ r; r has n entries.
  Eigen::VectorXd solve(const Eigen::VectorXd& r) const;

  /// n entries 1/A_ii (1 where A_ii is 0).
  const Eigen::VectorXd& inverse_diagonal() const { return inverse_diagonal_; }

 private:
  Eigen::VectorXd inverse_diagonal_;
};

}  // namespace volspline::linalg
