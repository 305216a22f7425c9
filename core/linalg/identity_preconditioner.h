// SPDX-License-Identifier: MIT
#pragma once

#include <algorithm>

#include <Eigen/Core>

#include "core/linalg/csr_matrix.h"

namespace volspline::linalg {

/// No preconditioning (M = I): plain conjugate gradients.
class IdentityPreconditioner {
 public:
  /// Nothing to precompute; accepts any square matrix.
  void compute(const CsrMatrix& a) { size_ = a.rows(); }

  /// z = r for n = a.rows() entries; r and z may alias.
  void solve(const double* r, double* z) const {
    if (r != z) std::copy(r, r + size_, z);
  }

  /// Returns r.
  Eigen::VectorXd solve(const Eigen::VectorXd& r) const { return r; }

 private:
  int size_ = 0;
};

}  // namespace volspline::linalg
