// SPDX-License-Identifier: MIT
#include "core/linalg/conjugate_gradient.h"

namespace volspline::linalg::detail {

namespace {

// Four interleaved partial sums combined in a fixed order: deterministic, and it breaks the
// add-latency chain that a single accumulator would impose on these memory-bound loops.
struct Sum4 {
  double s[4] = {0.0, 0.0, 0.0, 0.0};
  double total() const { return (s[0] + s[1]) + (s[2] + s[3]); }
};

// Rows per block of the lagged direction update: the slice of p that a block reads stays in
// cache between its update and its use, and the update itself is a contiguous, vectorizable loop.
constexpr int kBlockRows = 512;

template <class Direction>
double direction_spmv_impl(const CsrMatrix& a, Direction direction, double beta,
                           double* __restrict p, double* __restrict q) {
  const int n = a.rows();
  const int* offsets = a.row_offsets().data();
  const int* cols = a.col_indices().data();
  const double* vals = a.values().data();
  int updated = 0;
  double pq = 0.0;
  for (int block = 0; block < n; block += kBlockRows) {
    const int block_end = std::min(n, block + kBlockRows);
    // Entries of p up to the last column this block reads (and its own rows, for p·q) must be
    // new before the block's SpMV.
    int need = block_end;
    for (int i = block; i < block_end; ++i) {
      if (offsets[i + 1] > offsets[i]) need = std::max(need, cols[offsets[i + 1] - 1] + 1);
    }
    if (need > updated) {
      direction(updated, need, beta, p);
      updated = need;
    }
    for (int i = block; i < block_end; ++i) {
      double sum = 0.0;
      for (int k = offsets[i]; k < offsets[i + 1]; ++k) sum += vals[k] * p[cols[k]];
      q[i] = sum;
      pq += p[i] * sum;
    }
  }
  return pq;
}

}  // namespace

double residual(const CsrMatrix& a, const double* b, const double* x, double* r) {
  const int n = a.rows();
  const int* offsets = a.row_offsets().data();
  const int* cols = a.col_indices().data();
  const double* vals = a.values().data();
  double rr = 0.0;
  for (int i = 0; i < n; ++i) {
    double sum = 0.0;
    for (int k = offsets[i]; k < offsets[i + 1]; ++k) sum += vals[k] * x[cols[k]];
    const double ri = b[i] - sum;
    r[i] = ri;
    rr += ri * ri;
  }
  return rr;
}

double dot(int n, const double* a, const double* b) {
  Sum4 acc;
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    for (int j = 0; j < 4; ++j) acc.s[j] += a[i + j] * b[i + j];
  }
  for (; i < n; ++i) acc.s[0] += a[i] * b[i];
  return acc.total();
}

double direction_spmv(const CsrMatrix& a, const double* z, double beta, double* p, double* q) {
  return direction_spmv_impl(
      a,
      [z](int begin, int end, double beta, double* __restrict p) {
        for (int j = begin; j < end; ++j) p[j] = z[j] + beta * p[j];
      },
      beta, p, q);
}

double update(int n, double alpha, const double* __restrict p, const double* __restrict q,
              const double* __restrict scale, double* __restrict x, double* __restrict r,
              double* __restrict z, double* rz) {
  Sum4 rr_acc;
  if (scale) {
    Sum4 rz_acc;
    int i = 0;
    for (; i + 4 <= n; i += 4) {
      for (int j = 0; j < 4; ++j) {
        x[i + j] += alpha * p[i + j];
        const double ri = r[i + j] - alpha * q[i + j];
        const double zi = scale[i + j] * ri;
        r[i + j] = ri;
        z[i + j] = zi;
        rr_acc.s[j] += ri * ri;
        rz_acc.s[j] += ri * zi;
      }
    }
    for (; i < n; ++i) {
      x[i] += alpha * p[i];
      const double ri = r[i] - alpha * q[i];
      const double zi = scale[i] * ri;
      r[i] = ri;
      z[i] = zi;
      rr_acc.s[0] += ri * ri;
      rz_acc.s[0] += ri * zi;
    }
    *rz = rz_acc.total();
    return rr_acc.total();
  }
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    for (int j = 0; j < 4; ++j) {
      x[i + j] += alpha * p[i + j];
      const double ri = r[i + j] - alpha * q[i + j];
      r[i + j] = ri;
      rr_acc.s[j] += ri * ri;
    }
  }
  for (; i < n; ++i) {
    x[i] += alpha * p[i];
    const double ri = r[i] - alpha * q[i];
    r[i] = ri;
    rr_acc.s[0] += ri * ri;
  }
  return rr_acc.total();
}

double update_forward(const IncompleteCholesky0& ic, double alpha, const double* p,
                      const double* q, double* x, double* r, double* y) {
  const CsrMatrix& lower = ic.strict_lower();
  const int n = lower.rows();
  const int* offsets = lower.row_offsets().data();
  const int* cols = lower.col_indices().data();
  const double* vals = lower.values().data();
  const double* inv = ic.inverse_diagonal().data();
  double rr = 0.0;
  for (int i = 0; i < n; ++i) {
    x[i] += alpha * p[i];
    const double ri = r[i] - alpha * q[i];
    r[i] = ri;
    rr += ri * ri;
    double s = ri;
    for (int k = offsets[i]; k < offsets[i + 1]; ++k) s -= vals[k] * y[cols[k]];
    y[i] = s * inv[i];
  }
  return rr;
}

double backward_dot(const IncompleteCholesky0& ic, const double* r, double* y) {
  const CsrMatrix& upper = ic.strict_upper();
  const int n = upper.rows();
  const int* offsets = upper.row_offsets().data();
  const int* cols = upper.col_indices().data();
  const double* vals = upper.values().data();
  const double* inv = ic.inverse_diagonal().data();
  double rz = 0.0;
  for (int i = n - 1; i >= 0; --i) {
    double s = y[i];
    for (int k = offsets[i]; k < offsets[i + 1]; ++k) s -= vals[k] * y[cols[k]];
    const double zi = s * inv[i];
    y[i] = zi;
    rz += r[i] * zi;
  }
  return rz;
}

}  // namespace volspline::linalg::detail
