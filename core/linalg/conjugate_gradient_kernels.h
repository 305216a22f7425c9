// SPDX-License-Identifier: MIT
// Internal to ConjugateGradient (conjugate_gradient.h): the kernels of its iteration, defined in
// conjugate_gradient.cpp, and the traits that pick a preconditioner's fused paths.
#pragma once

#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/linalg/csr_matrix.h"
#include "core/linalg/incomplete_cholesky0.h"

namespace volspline::linalg {

namespace detail {

// Kernels of the CG iteration (conjugate_gradient.cpp). All arrays have n entries.
// The SpMV dominates the run time (streaming the matrix), so the solver keeps only the
// diagonal and the strict upper triangle: half the bytes per product of a full CSR matrix.

/// Strict-upper entries from which a product is cut into kSpmvParts row ranges (smaller
/// matrices keep one part: the products of a small fit are not worth a thread).
constexpr int kMinPartedSpmvNnz = 1 << 17;
/// Row ranges of a large matrix's product: a fixed count, never the thread count, so that the
/// rounding and hence the results are the same for every thread count.
constexpr int kSpmvParts = 4;
/// Fewest threads for which the parts run concurrently (below, one after another, same bits):
/// one thread already streams the matrix near the memory bandwidth, and on two threads of a
/// loaded machine the concurrent parts were slower (neghip's last level, 1.2M entries:
/// 2.0–2.8 ms per product against 1.4–1.8 ms).
constexpr int kMinSpmvThreads = 3;

/// Symmetric matrix as its diagonal plus strict upper triangle.
struct SymmetricMatrix {
  Eigen::VectorXd diagonal;  ///< n entries
  CsrMatrix strict_upper;    ///< n×n, entries with col > row
  /// First row of each part of the product and n at the end (1 or kSpmvParts parts, cut at
  /// equal strict-upper entry counts). Part t reads only its rows of strict_upper and
  /// accumulates its scattered terms (rows ≥ its first) privately; the parts are summed into
  /// q in part order, so they run in parallel with the same bits as one after the other.
  std::vector<int> part_rows;
  int threads = 1;
  /// Work space of the parts t ≥ 1, kept between products (a product of a large matrix would
  /// otherwise allocate and fault in fresh pages every time). One product at a time.
  mutable std::vector<double> scratch;
};
/// Diagonal and strict upper triangle of the square matrix a (the lower triangle is ignored);
/// `threads` (≥ 1; from kMinSpmvThreads on) run the parts of the products concurrently.
SymmetricMatrix symmetric_from_upper(const CsrMatrix& a, int threads = 1);
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

// Block kernels: the same arithmetic as their one-column counterparts, column by column, for
// up to kMaxBlock columns at once (the matrix or factor is read once for all of them).
constexpr int kMaxBlock = 4;
/// Per column: q += A p, pq = p·q.
void symmetric_spmv_block(const SymmetricMatrix& a, int k, const double* const* p,
                          double* const* q, double* pq);
/// Column pointers of update_forward_block.
struct BlockVectors {
  const double* p[kMaxBlock];
  const double* q[kMaxBlock];
  double* x[kMaxBlock];
  double* r[kMaxBlock];
  double* z[kMaxBlock];
};
/// Per column: update_forward with alpha[c] (y = v.z), rr[c] = r·r.
void update_forward_block(const IncompleteCholesky0& ic, int k, const double* alpha,
                          const BlockVectors& v, double* rr);
/// Per column: backward_dot, rz[c] = r·z.
void backward_dot_block(const IncompleteCholesky0& ic, int k, const double* const* r,
                        double* const* y, double* rz);

/// Whether a preconditioner offers solve_block(k, r, z) (k ≤ kMaxBlock columns at once).
template <class P, class = void>
struct HasBlockSolve : std::false_type {};
template <class P>
struct HasBlockSolve<P, std::void_t<decltype(std::declval<const P&>().solve_block(
                            0, std::declval<const double* const*>(), std::declval<double* const*>()))>>
    : std::true_type {};

/// Whether a preconditioner offers set_threads(int) (applied before its compute).
template <class P, class = void>
struct HasSetThreads : std::false_type {};
template <class P>
struct HasSetThreads<P, std::void_t<decltype(std::declval<P&>().set_threads(1))>> : std::true_type {};

}  // namespace detail

}  // namespace volspline::linalg
