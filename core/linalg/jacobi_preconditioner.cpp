// SPDX-License-Identifier: MIT
#include "core/linalg/jacobi_preconditioner.h"

#include <cassert>

namespace volspline::linalg {

void JacobiPreconditioner::compute(const CsrMatrix& a) {
  assert(a.rows() == a.cols());
  inverse_diagonal_ = a.diagonal();
  for (Eigen::Index i = 0; i < inverse_diagonal_.size(); ++i) {
    const double d = inverse_diagonal_[i];
    inverse_diagonal_[i] = d == 0.0 ? 1.0 : 1.0 / d;
  }
}

void JacobiPreconditioner::solve(const double* r, double* z) const {
  const double* inv = inverse_diagonal_.data();
  const Eigen::Index n = inverse_diagonal_.size();
  for (Eigen::Index i = 0; i < n; ++i) z[i] = inv[i] * r[i];
}

Eigen::VectorXd JacobiPreconditioner::solve(const Eigen::VectorXd& r) const {
  assert(r.size() == inverse_diagonal_.size());
  return inverse_diagonal_.cwiseProduct(r);
}

}  // namespace volspline::linalg
