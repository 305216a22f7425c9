// SPDX-License-Identifier: MIT
#pragma once

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/linalg/conjugate_gradient_kernels.h"
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
/// have fused fast paths. Deterministic (fixed summation order); set_threads parallelizes the
/// matrix products and the preconditioner's compute (not the triangular solves), with
/// bit-identical results.
template <class Preconditioner>
class ConjugateGradient {
 public:
  ConjugateGradient() = default;
  /// Same as compute(a).
  explicit ConjugateGradient(const CsrMatrix& a) { compute(a); }

  /// a: square n×n, symmetric positive definite, both triangles stored. Copies its diagonal
  /// and upper triangle and computes the preconditioner. A solve allocates its work arrays
  /// once, never in iterations.
  ConjugateGradient& compute(const CsrMatrix& a) {
    assert(a.rows() == a.cols());
    matrix_ = detail::symmetric_from_upper(a, threads_);
    if constexpr (detail::HasSetThreads<Preconditioner>::value) preconditioner_.set_threads(threads_);
    preconditioner_.compute(a);
    return *this;
  }

  /// Solves A x = b from x0 = 0. b is n×1 (returns a vector) or n×k (returns n×k: k solves
  /// run in lockstep, each bit-identical to its lone solve; info() is the worst, iterations()
  /// and residual() the largest over the columns).
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

  /// Threads of the matrix products (large matrices, from detail::kMinSpmvThreads on) and
  /// of the preconditioner's compute if it has set_threads (≥ 1, default 1: none created),
  /// applied by the next compute(). Results are bit-identical for every count.
  ConjugateGradient& set_threads(int threads) {
    assert(threads >= 1);
    threads_ = threads;
    return *this;
  }

  const Preconditioner& preconditioner() const { return preconditioner_; }

  /// n of the last compute (0 before).
  int size() const { return static_cast<int>(matrix_.diagonal.size()); }

 private:
  // Where each column of a block solve stands in the iteration of the class comment.
  enum class Phase {
    Check,    // true residual rr just computed: converged, out of budget, or (re)start
    Iterate,  // inside the recursive-residual loop
    Done,
  };
  struct Column {
    const double* b;
    double *x, *r, *p, *q, *z;
    double bb, threshold, rr, rz, rz_new, beta, pq;
    int iterations;
    SolverInfo info;
    Phase phase;
  };

  // Hestenes–Stiefel PCG with Eigen's stopping rule, run on all columns in lockstep: the
  // matrix (and IC(0)'s factor) is streamed once per iteration for all of them, and each
  // column does exactly the arithmetic of a lone solve, so results do not depend on k.
  template <class Rhs, class Dest>
  void solve_columns(const Eigen::MatrixBase<Rhs>& b, Dest& x) {
    assert(b.rows() == size());
    const int n = size();
    const int k = static_cast<int>(b.cols());
    b_ = b;
    r_.resize(n, k);
    p_.resize(n, k);
    q_.resize(n, k);
    z_.resize(n, k);
    columns_.resize(k);
    const int max_iter = max_iterations();
    for (int c = 0; c < k; ++c) {
      Column& col = columns_[c];
      col = Column{};
      col.b = b_.col(c).data();
      col.x = x.data() + std::ptrdiff_t(c) * n;
      col.r = r_.col(c).data();
      col.p = p_.col(c).data();
      col.q = q_.col(c).data();
      col.z = z_.col(c).data();
      col.bb = detail::dot(n, col.b, col.b);
      col.info = SolverInfo::NotConverged;
      col.phase = Phase::Check;
      if (!std::isfinite(col.bb)) {
        col.info = SolverInfo::NumericalIssue;
        col.rr = std::numeric_limits<double>::quiet_NaN();
        col.bb = 1.0;
        col.phase = Phase::Done;
      } else if (col.bb == 0.0) {
        std::fill(col.x, col.x + n, 0.0);
        col.info = SolverInfo::Success;
        col.rr = 0.0;
        col.bb = 1.0;
        col.phase = Phase::Done;
      } else {
        col.threshold = std::max(tolerance_ * tolerance_ * col.bb, std::numeric_limits<double>::min());
        col.rr = detail::residual(matrix_, col.b, col.x, col.r);
      }
    }
    std::vector<Column*> active, survivors;
    active.reserve(k);
    survivors.reserve(k);
    while (true) {
      // Outer loop head: decide on the true residual, else (re)start with p = z.
      for (Column& col : columns_) {
        if (col.phase != Phase::Check) continue;
        if (!std::isfinite(col.rr)) {
          finish(col, SolverInfo::NumericalIssue);
        } else if (col.rr < col.threshold) {
          finish(col, SolverInfo::Success);
        } else if (col.iterations >= max_iter) {
          finish(col, SolverInfo::NotConverged);
        } else {
          std::fill(col.p, col.p + n, 0.0);
          col.rz = precondition(col);
          col.beta = 0.0;
          col.phase = Phase::Iterate;
        }
      }
      // Inner loop head and the new direction.
      active.clear();
      for (Column& col : columns_) {
        if (col.phase != Phase::Iterate) continue;
        if (col.iterations >= max_iter) {
          check(col);
        } else if (!(col.rz > 0.0) || !std::isfinite(col.rz)) {
          finish(col, SolverInfo::NumericalIssue);
        } else {
          new_direction(col);
          active.push_back(&col);
        }
      }
      if (active.empty()) {
        bool done = true;
        for (const Column& col : columns_) done = done && col.phase == Phase::Done;
        if (done) break;
        continue;
      }
      spmv(active);
      survivors.clear();
      for (Column* col : active) {
        if (!(col->pq > 0.0) || !std::isfinite(col->pq)) {
          finish(*col, SolverInfo::NumericalIssue);
        } else {
          survivors.push_back(col);
        }
      }
      update(survivors);
      active.clear();
      for (Column* col : survivors) {
        ++col->iterations;
        // The recursive residual claims convergence (or broke down): the loop head decides
        // on the true residual.
        if (!std::isfinite(col->rr) || col->rr < col->threshold) {
          check(*col);
        } else {
          active.push_back(col);
        }
      }
      precondition_after_update(active);
      for (Column* col : active) {
        col->beta = col->rz_new / col->rz;
        col->rz = col->rz_new;
      }
    }
    info_ = SolverInfo::Success;
    iterations_ = 0;
    residual_ = 0.0;
    for (const Column& col : columns_) {
      if (static_cast<int>(col.info) > static_cast<int>(info_)) info_ = col.info;
      iterations_ = std::max(iterations_, col.iterations);
      residual_ = std::max(residual_, std::sqrt(col.rr / col.bb));
    }
  }

  void check(Column& col) {
    col.rr = detail::residual(matrix_, col.b, col.x, col.r);
    col.phase = Phase::Check;
  }

  void finish(Column& col, SolverInfo info) {
    col.info = info;
    if (info == SolverInfo::NumericalIssue)
      col.rr = detail::residual(matrix_, col.b, col.x, col.r);
    col.phase = Phase::Done;
  }

  // Preconditioned direction z = M⁻¹ r of the column's residual; returns r·z.
  double precondition(Column& col) {
    const int n = size();
    if constexpr (std::is_same_v<Preconditioner, IdentityPreconditioner>) {
      return col.rr;
    } else if constexpr (std::is_same_v<Preconditioner, JacobiPreconditioner>) {
      const double* inv = preconditioner_.inverse_diagonal().data();
      for (int i = 0; i < n; ++i) col.z[i] = inv[i] * col.r[i];
      return detail::dot(n, col.r, col.z);
    } else {
      preconditioner_.solve(col.r, col.z);
      return detail::dot(n, col.r, col.z);
    }
  }

  void new_direction(Column& col) {
    const int n = size();
    if constexpr (std::is_same_v<Preconditioner, IdentityPreconditioner>) {
      detail::new_direction(n, col.r, nullptr, col.beta, col.p, col.q);
    } else if constexpr (std::is_same_v<Preconditioner, JacobiPreconditioner>) {
      detail::new_direction(n, col.r, preconditioner_.inverse_diagonal().data(), col.beta, col.p,
                            col.q);
    } else {
      detail::new_direction(n, col.z, nullptr, col.beta, col.p, col.q);
    }
  }

  // q = A p and p·q for every listed column, streaming A once per block of columns.
  void spmv(const std::vector<Column*>& cols) {
    for (std::size_t first = 0; first < cols.size(); first += detail::kMaxBlock) {
      const int m = static_cast<int>(std::min<std::size_t>(detail::kMaxBlock, cols.size() - first));
      const double* p[detail::kMaxBlock];
      double* q[detail::kMaxBlock];
      double pq[detail::kMaxBlock];
      for (int c = 0; c < m; ++c) {
        p[c] = cols[first + c]->p;
        q[c] = cols[first + c]->q;
      }
      detail::symmetric_spmv_block(matrix_, m, p, q, pq);
      for (int c = 0; c < m; ++c) cols[first + c]->pq = pq[c];
    }
  }

  // x += αp, r −= αq with α = rz/pq; sets rr (and rz_new where the preconditioner is fused).
  void update(const std::vector<Column*>& cols) {
    const int n = size();
    if constexpr (std::is_same_v<Preconditioner, IncompleteCholesky0>) {
      for (std::size_t first = 0; first < cols.size(); first += detail::kMaxBlock) {
        const int m = static_cast<int>(std::min<std::size_t>(detail::kMaxBlock, cols.size() - first));
        detail::BlockVectors v;
        double alpha[detail::kMaxBlock], rr[detail::kMaxBlock];
        for (int c = 0; c < m; ++c) {
          Column& col = *cols[first + c];
          alpha[c] = col.rz / col.pq;
          v.p[c] = col.p;
          v.q[c] = col.q;
          v.x[c] = col.x;
          v.r[c] = col.r;
          v.z[c] = col.z;
        }
        detail::update_forward_block(preconditioner_, m, alpha, v, rr);
        for (int c = 0; c < m; ++c) cols[first + c]->rr = rr[c];
      }
    } else {
      for (Column* col : cols) {
        const double alpha = col->rz / col->pq;
        if constexpr (std::is_same_v<Preconditioner, IdentityPreconditioner>) {
          col->rr = detail::update(n, alpha, col->p, col->q, nullptr, col->x, col->r, nullptr);
          col->rz_new = col->rr;
        } else if constexpr (std::is_same_v<Preconditioner, JacobiPreconditioner>) {
          col->rr = detail::update(n, alpha, col->p, col->q,
                                   preconditioner_.inverse_diagonal().data(), col->x, col->r,
                                   &col->rz_new);
        } else {
          col->rr = detail::update(n, alpha, col->p, col->q, nullptr, col->x, col->r, nullptr);
        }
      }
    }
  }

  // z = M⁻¹ r and rz_new = r·z after an update, for preconditioners not fused into update.
  void precondition_after_update(const std::vector<Column*>& cols) {
    const int n = size();
    if constexpr (std::is_same_v<Preconditioner, IncompleteCholesky0>) {
      for (std::size_t first = 0; first < cols.size(); first += detail::kMaxBlock) {
        const int m = static_cast<int>(std::min<std::size_t>(detail::kMaxBlock, cols.size() - first));
        const double* r[detail::kMaxBlock];
        double* z[detail::kMaxBlock];
        double rz[detail::kMaxBlock];
        for (int c = 0; c < m; ++c) {
          r[c] = cols[first + c]->r;
          z[c] = cols[first + c]->z;
        }
        detail::backward_dot_block(preconditioner_, m, r, z, rz);
        for (int c = 0; c < m; ++c) cols[first + c]->rz_new = rz[c];
      }
    } else if constexpr (!std::is_same_v<Preconditioner, IdentityPreconditioner> &&
                         !std::is_same_v<Preconditioner, JacobiPreconditioner>) {
      if constexpr (detail::HasBlockSolve<Preconditioner>::value) {
        for (std::size_t first = 0; first < cols.size(); first += detail::kMaxBlock) {
          const int m =
              static_cast<int>(std::min<std::size_t>(detail::kMaxBlock, cols.size() - first));
          const double* r[detail::kMaxBlock];
          double* z[detail::kMaxBlock];
          for (int c = 0; c < m; ++c) {
            r[c] = cols[first + c]->r;
            z[c] = cols[first + c]->z;
          }
          preconditioner_.solve_block(m, r, z);
        }
      } else {
        for (Column* col : cols) preconditioner_.solve(col->r, col->z);
      }
      for (Column* col : cols) col->rz_new = detail::dot(n, col->r, col->z);
    }
  }

  detail::SymmetricMatrix matrix_;
  Preconditioner preconditioner_;
  double tolerance_ = 1e-10;
  int max_iterations_ = -1;
  int threads_ = 1;
  Eigen::MatrixXd b_, r_, p_, q_, z_;  // n×k work arrays of the last solve, one column each
  std::vector<Column> columns_;
  SolverInfo info_ = SolverInfo::Success;
  int iterations_ = 0;
  double residual_ = 0.0;
};

}  // namespace volspline::linalg
