// SPDX-License-Identifier: MIT
#pragma once

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <type_traits>

#include <Eigen/Core>

#include "core/linalg/csr_matrix.h"
#include "core/linalg/identity_preconditioner.h"
#include "core/linalg/incomplete_cholesky0.h"
#include "core/linalg/jacobi_preconditioner.h"

namespace volspline::linalg {

/// Outcome of an iterative solve. Non-convergence is reported here, never thrown.
enum class SolverInfo {
  Success,         ///< ‖b − A x‖ ≤ tolerance·‖b‖ (checked on the true residual)
  NotConverged,    ///< max_iterations reached first
  NumericalIssue,  ///< pᵀAp ≤ 0, rᵀM⁻¹r ≤ 0 or NaN/Inf met: A or M is not SPD, or bad data
};

namespace detail {

// Kernels of the CG iteration (conjugate_gradient.cpp). All arrays have n entries.
// The SpMV dominates the run time (streaming the matrix), so the solver keeps only the
// diagonal and the strict upper triangle: half the bytes per product of a full CSR matrix.

/// Symmetric matrix as its diagonal plus strict upper triangle.
struct SymmetricMatrix {
  Eigen::VectorXd diagonal;  ///< n entries
  CsrMatrix strict_upper;    ///< n×n, entries with col > row
};
/// Diagonal and strict upper triangle of the square matrix a (the lower triangle is ignored).
SymmetricMatrix symmetric_from_upper(const CsrMatrix& a);
/// q += A p (q zeroed by the caller for q = A p); returns p·q.
double symmetric_spmv(const SymmetricMatrix& a, const double* p, double* q);
/// r = b − A x; returns r·r.
double residual(const SymmetricMatrix& a, const double* b, const double* x, double* r);
/// Returns a·b with a fixed summation order.
double dot(int n, const double* a, const double* b);
/// p = scale∘z + beta·p (scale null: p = z + beta·p) and q = 0.
void new_direction(int n, const double* z, const double* scale, double beta, double* p,
                   double* q);
/// x += alpha·p, r −= alpha·q; returns r·r, and r·(scale∘r) in *rz when scale is not null.
double update(int n, double alpha, const double* p, const double* q, const double* scale,
              double* x, double* r, double* rz);
/// As update, then y = L⁻¹ r (forward substitution with IC(0)); returns r·r.
double update_forward(const IncompleteCholesky0& ic, double alpha, const double* p,
                      const double* q, double* x, double* r, double* y);
/// In place y → z = L⁻ᵀ y (backward substitution with IC(0)); returns r·z.
double backward_dot(const IncompleteCholesky0& ic, const double* r, double* y);

}  // namespace detail

/// Preconditioned conjugate gradients for a symmetric positive definite CsrMatrix, after
/// Eigen's ConjugateGradient (same iteration and stopping rule).
///
/// Usage: compute(A) once (copies the diagonal and upper triangle of A, so A may be destroyed
/// afterwards, and builds the preconditioner), then solve(b) / solve(b, x0) any number of
/// times. Symmetry is a precondition: the iteration reads only the diagonal and the upper
/// triangle (as Eigen's Upper mode) and IncompleteCholesky0 only the lower one.
/// Stopping: ‖r‖ ≤ tolerance·‖b‖ as Eigen, where r is the recursive residual; on that event the
/// true residual b − A x is recomputed and CG restarts from x if it is still too large, so
/// Success always means the true relative residual is within tolerance. b = 0 gives x = 0.
/// iterations() counts updates of x; Eigen reports one less for the same run (it does not
/// count the update that converged).
/// Preconditioner: a type with compute(const CsrMatrix&) and solve(const double* r, double* z)
/// (z = M⁻¹ r, M SPD); IdentityPreconditioner, JacobiPreconditioner and IncompleteCholesky0
/// have fused fast paths. Single-threaded and deterministic (fixed summation order).
template <class Preconditioner>
class ConjugateGradient {
 public:
  ConjugateGradient() = default;
  /// Same as compute(a).
  explicit ConjugateGradient(const CsrMatrix& a) { compute(a); }

  /// a: square n×n, symmetric positive definite, both triangles stored. Copies its diagonal
  /// and upper triangle, computes the preconditioner and allocates all work vectors, so that
  /// solves do not allocate in iterations.
  ConjugateGradient& compute(const CsrMatrix& a) {
    assert(a.rows() == a.cols());
    matrix_ = detail::symmetric_from_upper(a);
    preconditioner_.compute(a);
    const int n = a.rows();
    r_.resize(n);
    p_.resize(n);
    q_.resize(n);
    z_.resize(n);
    return *this;
  }

  /// Solves A x = b from x0 = 0. b is n×1 (returns a vector) or n×k (returns n×k, k solves;
  /// info() is the worst, iterations() and residual() the largest over the columns).
  template <class Rhs>
  Eigen::Matrix<double, Eigen::Dynamic, Rhs::ColsAtCompileTime == 1 ? 1 : Eigen::Dynamic> solve(
      const Eigen::MatrixBase<Rhs>& b) {
    Eigen::Matrix<double, Eigen::Dynamic, Rhs::ColsAtCompileTime == 1 ? 1 : Eigen::Dynamic> x =
        Eigen::MatrixXd::Zero(b.rows(), b.cols());
    solve_columns(b, x);
    return x;
  }

  /// Solves A x = b starting from the guess x0 (same shape as b): warm start.
  template <class Rhs, class Guess>
  Eigen::Matrix<double, Eigen::Dynamic, Rhs::ColsAtCompileTime == 1 ? 1 : Eigen::Dynamic> solve(
      const Eigen::MatrixBase<Rhs>& b, const Eigen::MatrixBase<Guess>& x0) {
    assert(x0.rows() == b.rows() && x0.cols() == b.cols());
    Eigen::Matrix<double, Eigen::Dynamic, Rhs::ColsAtCompileTime == 1 ? 1 : Eigen::Dynamic> x =
        x0;
    solve_columns(b, x);
    return x;
  }

  /// Outcome of the last solve.
  SolverInfo info() const { return info_; }
  /// Number of x updates in the last solve (max over columns).
  int iterations() const { return iterations_; }
  /// Relative residual ‖b − A x‖/‖b‖ of the last solve (max over columns; 0 if b = 0).
  double residual() const { return residual_; }

  /// Relative tolerance on ‖b − A x‖/‖b‖; default 1e-10. Asserts tol_rel ≥ 0.
  ConjugateGradient& set_tolerance(double tol_rel) {
    assert(tol_rel >= 0.0);
    tolerance_ = tol_rel;
    return *this;
  }
  double tolerance() const { return tolerance_; }

  /// Iteration cap; default (or any negative value) 2·n, as Eigen.
  ConjugateGradient& set_max_iterations(int max_iterations) {
    max_iterations_ = max_iterations;
    return *this;
  }
  int max_iterations() const {
    return max_iterations_ >= 0 ? max_iterations_ : 2 * size();
  }

  const Preconditioner& preconditioner() const { return preconditioner_; }

  /// n of the last compute (0 before).
  int size() const { return static_cast<int>(matrix_.diagonal.size()); }

 private:
  template <class Rhs, class Dest>
  void solve_columns(const Eigen::MatrixBase<Rhs>& b, Dest& x) {
    assert(b.rows() == size());
    info_ = SolverInfo::Success;
    iterations_ = 0;
    residual_ = 0.0;
    Eigen::VectorXd b_col;
    Eigen::VectorXd x_col;
    for (Eigen::Index c = 0; c < b.cols(); ++c) {
      b_col = b.col(c);
      x_col = x.col(c);
      const SolverInfo info = solve_one(b_col.data(), x_col.data());
      x.col(c) = x_col;
      if (static_cast<int>(info) > static_cast<int>(info_)) info_ = info;
      iterations_ = std::max(iterations_, last_iterations_);
      residual_ = std::max(residual_, last_residual_);
    }
  }

  // Preconditioned direction z = M⁻¹ r of the current residual; returns r·z.
  double precondition(double rr) {
    if constexpr (std::is_same_v<Preconditioner, IdentityPreconditioner>) {
      return rr;
    } else if constexpr (std::is_same_v<Preconditioner, JacobiPreconditioner>) {
      z_ = preconditioner_.inverse_diagonal().cwiseProduct(r_);
      return detail::dot(static_cast<int>(r_.size()), r_.data(), z_.data());
    } else {
      preconditioner_.solve(r_.data(), z_.data());
      return detail::dot(static_cast<int>(r_.size()), r_.data(), z_.data());
    }
  }

  // Algorithm: Hestenes–Stiefel PCG with Eigen's stopping rule; see the class comment.
  SolverInfo solve_one(const double* b, double* x) {
    const detail::SymmetricMatrix& a = matrix_;
    const int n = size();
    last_iterations_ = 0;
    last_residual_ = 0.0;
    const double bb = detail::dot(n, b, b);
    if (!std::isfinite(bb)) {
      last_residual_ = std::numeric_limits<double>::quiet_NaN();
      return SolverInfo::NumericalIssue;
    }
    if (bb == 0.0) {
      std::fill(x, x + n, 0.0);
      return SolverInfo::Success;
    }
    const double threshold =
        std::max(tolerance_ * tolerance_ * bb, std::numeric_limits<double>::min());
    const int max_iter = max_iterations();
    double rr = detail::residual(a, b, x, r_.data());
    SolverInfo info = SolverInfo::NotConverged;
    int iter = 0;
    while (true) {
      if (!std::isfinite(rr)) {
        info = SolverInfo::NumericalIssue;
        break;
      }
      if (rr < threshold) {
        info = SolverInfo::Success;
        break;
      }
      if (iter >= max_iter) break;
      // (Re)start: p = z via beta = 0 on a zeroed p.
      p_.setZero();
      double rz = precondition(rr);
      double beta = 0.0;
      while (iter < max_iter) {
        if (!(rz > 0.0) || !std::isfinite(rz)) {
          info = SolverInfo::NumericalIssue;
          break;
        }
        if constexpr (std::is_same_v<Preconditioner, IdentityPreconditioner>) {
          detail::new_direction(n, r_.data(), nullptr, beta, p_.data(), q_.data());
        } else if constexpr (std::is_same_v<Preconditioner, JacobiPreconditioner>) {
          detail::new_direction(n, r_.data(), preconditioner_.inverse_diagonal().data(), beta,
                                p_.data(), q_.data());
        } else {
          detail::new_direction(n, z_.data(), nullptr, beta, p_.data(), q_.data());
        }
        const double pq = detail::symmetric_spmv(a, p_.data(), q_.data());
        if (!(pq > 0.0) || !std::isfinite(pq)) {
          info = SolverInfo::NumericalIssue;
          break;
        }
        const double alpha = rz / pq;
        double rz_new = 0.0;
        if constexpr (std::is_same_v<Preconditioner, IdentityPreconditioner>) {
          rr = detail::update(n, alpha, p_.data(), q_.data(), nullptr, x, r_.data(), nullptr);
          rz_new = rr;
        } else if constexpr (std::is_same_v<Preconditioner, JacobiPreconditioner>) {
          rr = detail::update(n, alpha, p_.data(), q_.data(),
                              preconditioner_.inverse_diagonal().data(), x, r_.data(), &rz_new);
        } else if constexpr (std::is_same_v<Preconditioner, IncompleteCholesky0>) {
          rr = detail::update_forward(preconditioner_, alpha, p_.data(), q_.data(), x,
                                      r_.data(), z_.data());
        } else {
          rr = detail::update(n, alpha, p_.data(), q_.data(), nullptr, x, r_.data(), nullptr);
        }
        ++iter;
        if (!std::isfinite(rr)) break;
        if (rr < threshold) break;
        if constexpr (std::is_same_v<Preconditioner, IncompleteCholesky0>) {
          rz_new = detail::backward_dot(preconditioner_, r_.data(), z_.data());
        } else if constexpr (!std::is_same_v<Preconditioner, IdentityPreconditioner> &&
                             !std::is_same_v<Preconditioner, JacobiPreconditioner>) {
          preconditioner_.solve(r_.data(), z_.data());
          rz_new = detail::dot(n, r_.data(), z_.data());
        }
        beta = rz_new / rz;
        rz = rz_new;
      }
      if (info == SolverInfo::NumericalIssue) break;
      // The recursive residual claims convergence, or the budget ran out: the loop head
      // decides on the true residual.
      rr = detail::residual(a, b, x, r_.data());
    }
    last_iterations_ = iter;
    if (info == SolverInfo::NumericalIssue) rr = detail::residual(a, b, x, r_.data());
    last_residual_ = std::sqrt(rr / bb);
    return info;
  }

  detail::SymmetricMatrix matrix_;
  Preconditioner preconditioner_;
  double tolerance_ = 1e-10;
  int max_iterations_ = -1;
  Eigen::VectorXd r_, p_, q_, z_;
  SolverInfo info_ = SolverInfo::Success;
  int iterations_ = 0;
  double residual_ = 0.0;
  int last_iterations_ = 0;
  double last_residual_ = 0.0;
};

}  // namespace volspline::linalg
