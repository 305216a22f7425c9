// SPDX-License-Identifier: MIT
#include "core/linalg/conjugate_gradient.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <vector>

#include "core/linalg/parallel_for.h"

namespace volspline::linalg::detail {

namespace {

// Four interleaved partial sums combined in a fixed order: deterministic, and it breaks the
// add-latency chain that a single accumulator would impose on these memory-bound loops.
struct Sum4 {
  double s[4] = {0.0, 0.0, 0.0, 0.0};
  double total() const { return (s[0] + s[1]) + (s[2] + s[3]); }
};

}  // namespace

SymmetricMatrix symmetric_from_upper(const CsrMatrix& a, int threads) {
  const int n = a.rows();
  const std::vector<int>& off = a.row_offsets();
  const std::vector<int>& col = a.col_indices();
  const std::vector<double>& val = a.values();
  SymmetricMatrix s;
  s.diagonal = Eigen::VectorXd::Zero(n);
  std::vector<int> offsets(n + 1, 0);
  std::vector<int> cols;
  std::vector<double> vals;
  cols.reserve(a.nnz() / 2 + 1);
  vals.reserve(a.nnz() / 2 + 1);
  for (int i = 0; i < n; ++i) {
    for (int k = off[i]; k < off[i + 1]; ++k) {
      if (col[k] == i) {
        s.diagonal[i] = val[k];
      } else if (col[k] > i) {
        cols.push_back(col[k]);
        vals.push_back(val[k]);
      }
    }
    offsets[i + 1] = static_cast<int>(cols.size());
  }
  s.strict_upper =
      CsrMatrix::from_arrays(n, n, std::move(offsets), std::move(cols), std::move(vals));
  s.threads = std::max(1, threads);
  const int nnz = s.strict_upper.nnz();
  const int parts = nnz >= kMinPartedSpmvNnz ? kSpmvParts : 1;
  const std::vector<int>& up = s.strict_upper.row_offsets();
  s.part_rows.assign(1, 0);
  for (int t = 1; t < parts; ++t) {
    // First row whose entries start at or after t/parts of all entries.
    const long long target = static_cast<long long>(nnz) * t / parts;
    const int row = static_cast<int>(std::lower_bound(up.begin(), up.end(), target) - up.begin());
    s.part_rows.push_back(std::clamp(row, s.part_rows.back(), n));
  }
  s.part_rows.push_back(n);
  return s;
}

double residual(const SymmetricMatrix& a, const double* b, const double* x, double* r) {
  const int n = a.strict_upper.rows();
  std::fill(r, r + n, 0.0);
  symmetric_spmv(a, x, r);
  Sum4 acc;
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    for (int j = 0; j < 4; ++j) {
      const double ri = b[i + j] - r[i + j];
      r[i + j] = ri;
      acc.s[j] += ri * ri;
    }
  }
  for (; i < n; ++i) {
    r[i] = b[i] - r[i];
    acc.s[0] += r[i] * r[i];
  }
  return acc.total();
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

void new_direction(int n, const double* __restrict z, const double* __restrict scale,
                   double beta, double* __restrict p, double* __restrict q) {
  if (scale) {
    for (int i = 0; i < n; ++i) {
      p[i] = scale[i] * z[i] + beta * p[i];
      q[i] = 0.0;
    }
  } else {
    for (int i = 0; i < n; ++i) {
      p[i] = z[i] + beta * p[i];
      q[i] = 0.0;
    }
  }
}

double update(int n, double alpha, const double* __restrict p, const double* __restrict q,
              const double* __restrict scale, double* __restrict x, double* __restrict r,
              double* rz) {
  Sum4 rr_acc;
  if (scale) {
    Sum4 rz_acc;
    int i = 0;
    for (; i + 4 <= n; i += 4) {
      for (int j = 0; j < 4; ++j) {
        x[i + j] += alpha * p[i + j];
        const double ri = r[i + j] - alpha * q[i + j];
        r[i + j] = ri;
        rr_acc.s[j] += ri * ri;
        rz_acc.s[j] += ri * ri * scale[i + j];
      }
    }
    for (; i < n; ++i) {
      x[i] += alpha * p[i];
      const double ri = r[i] - alpha * q[i];
      r[i] = ri;
      rr_acc.s[0] += ri * ri;
      rz_acc.s[0] += ri * ri * scale[i];
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

namespace {

// Rows [begin, end) of the product: acc[i − first] gets the diagonal and upper terms of row i
// added to the terms scattered into it so far, and every row j > i the term A_ij p_i scattered
// into acc[j − first]. With acc = q, first = 0 and one part this is the plain one-pass symmetric
// product.
template <int K>
void spmv_part(const SymmetricMatrix& a, int begin, int end, int first, const double* const* p,
               double* const* acc) {
  const int* offsets = a.strict_upper.row_offsets().data();
  const int* cols = a.strict_upper.col_indices().data();
  const double* vals = a.strict_upper.values().data();
  const double* diag = a.diagonal.data();
  for (int i = begin; i < end; ++i) {
    double pi[K], sum[K];
    for (int c = 0; c < K; ++c) {
      pi[c] = p[c][i];
      sum[c] = acc[c][i - first] + diag[i] * pi[c];
    }
    for (int k = offsets[i]; k < offsets[i + 1]; ++k) {
      const int j = cols[k];
      const double v = vals[k];
      for (int c = 0; c < K; ++c) {
        sum[c] += v * p[c][j];
        acc[c][j - first] += v * pi[c];
      }
    }
    for (int c = 0; c < K; ++c) acc[c][i - first] = sum[c];
  }
}

template <int K>
void spmv_block(const SymmetricMatrix& a, const double* const* p, double* const* q, double* pq) {
  const int n = a.strict_upper.rows();
  const int parts = static_cast<int>(a.part_rows.size()) - 1;
  if (parts <= 1) {
    spmv_part<K>(a, 0, n, 0, p, q);
  } else {
    // Part 0 works in q itself; part t ≥ 1 in a private array over rows [part_rows[t], n)
    // (stored from index 0), added to q afterwards in part order.
    std::array<std::size_t, (kSpmvParts - 1) * K + 1> start{};
    for (int t = 1; t < parts; ++t)
      for (int c = 0; c < K; ++c) {
        const std::size_t slot = static_cast<std::size_t>(t - 1) * K + c;
        start[slot + 1] = start[slot] + static_cast<std::size_t>(n - a.part_rows[t]);
      }
    if (a.scratch.size() < start.back()) a.scratch.resize(start.back());
    double* scratch = a.scratch.data();
    parallel_for(a.threads >= kMinSpmvThreads ? a.threads : 1, parts, [&](int t) {
      double* acc[K];
      const int first = t == 0 ? 0 : a.part_rows[t];
      for (int c = 0; c < K; ++c) {
        if (t == 0) {
          acc[c] = q[c];
        } else {
          const std::size_t slot = static_cast<std::size_t>(t - 1) * K + c;
          acc[c] = scratch + start[slot];
          std::fill(acc[c], acc[c] + (start[slot + 1] - start[slot]), 0.0);
        }
      }
      spmv_part<K>(a, a.part_rows[t], a.part_rows[t + 1], first, p, acc);
    });
    for (int t = 1; t < parts; ++t) {
      const int first = a.part_rows[t];
      for (int c = 0; c < K; ++c) {
        const double* buffer = scratch + start[static_cast<std::size_t>(t - 1) * K + c];
        double* qc = q[c];
        for (int j = first; j < n; ++j) qc[j] += buffer[j - first];
      }
    }
  }
  for (int c = 0; c < K; ++c) {
    double dot = 0.0;
    for (int i = 0; i < n; ++i) dot += p[c][i] * q[c][i];
    pq[c] = dot;
  }
}

template <int K>
void update_forward_k(const IncompleteCholesky0& ic, const double* alpha, const BlockVectors& v,
                      double* rr) {
  const CsrMatrix& lower = ic.strict_lower();
  const int n = lower.rows();
  const int* offsets = lower.row_offsets().data();
  const int* cols = lower.col_indices().data();
  const double* vals = lower.values().data();
  const double* inv = ic.inverse_diagonal().data();
  double acc[K] = {};
  for (int i = 0; i < n; ++i) {
    double s[K];
    for (int c = 0; c < K; ++c) {
      v.x[c][i] += alpha[c] * v.p[c][i];
      const double ri = v.r[c][i] - alpha[c] * v.q[c][i];
      v.r[c][i] = ri;
      acc[c] += ri * ri;
      s[c] = ri;
    }
    for (int k = offsets[i]; k < offsets[i + 1]; ++k) {
      const double factor = vals[k];
      const int j = cols[k];
      for (int c = 0; c < K; ++c) s[c] -= factor * v.z[c][j];
    }
    for (int c = 0; c < K; ++c) v.z[c][i] = s[c] * inv[i];
  }
  for (int c = 0; c < K; ++c) rr[c] = acc[c];
}

template <int K>
void backward_dot_k(const IncompleteCholesky0& ic, const double* const* r, double* const* y,
                    double* rz) {
  const CsrMatrix& upper = ic.strict_upper();
  const int n = upper.rows();
  const int* offsets = upper.row_offsets().data();
  const int* cols = upper.col_indices().data();
  const double* vals = upper.values().data();
  const double* inv = ic.inverse_diagonal().data();
  double acc[K] = {};
  for (int i = n - 1; i >= 0; --i) {
    double s[K];
    for (int c = 0; c < K; ++c) s[c] = y[c][i];
    for (int k = offsets[i]; k < offsets[i + 1]; ++k) {
      const double u = vals[k];
      const int j = cols[k];
      for (int c = 0; c < K; ++c) s[c] -= u * y[c][j];
    }
    for (int c = 0; c < K; ++c) {
      const double zi = s[c] * inv[i];
      y[c][i] = zi;
      acc[c] += r[c][i] * zi;
    }
  }
  for (int c = 0; c < K; ++c) rz[c] = acc[c];
}

}  // namespace

double symmetric_spmv(const SymmetricMatrix& a, const double* p, double* q) {
  double pq;
  spmv_block<1>(a, &p, &q, &pq);
  return pq;
}

double update_forward(const IncompleteCholesky0& ic, double alpha, const double* p,
                      const double* q, double* x, double* r, double* y) {
  BlockVectors v;
  v.p[0] = p;
  v.q[0] = q;
  v.x[0] = x;
  v.r[0] = r;
  v.z[0] = y;
  double rr;
  update_forward_k<1>(ic, &alpha, v, &rr);
  return rr;
}

double backward_dot(const IncompleteCholesky0& ic, const double* r, double* y) {
  double rz;
  backward_dot_k<1>(ic, &r, &y, &rz);
  return rz;
}

void symmetric_spmv_block(const SymmetricMatrix& a, int k, const double* const* p,
                          double* const* q, double* pq) {
  switch (k) {
    case 1: spmv_block<1>(a, p, q, pq); break;
    case 2: spmv_block<2>(a, p, q, pq); break;
    case 3: spmv_block<3>(a, p, q, pq); break;
    case 4: spmv_block<4>(a, p, q, pq); break;
    default: assert(false);
  }
}

void update_forward_block(const IncompleteCholesky0& ic, int k, const double* alpha,
                          const BlockVectors& v, double* rr) {
  switch (k) {
    case 1: update_forward_k<1>(ic, alpha, v, rr); break;
    case 2: update_forward_k<2>(ic, alpha, v, rr); break;
    case 3: update_forward_k<3>(ic, alpha, v, rr); break;
    case 4: update_forward_k<4>(ic, alpha, v, rr); break;
    default: assert(false);
  }
}

void backward_dot_block(const IncompleteCholesky0& ic, int k, const double* const* r,
                        double* const* y, double* rz) {
  switch (k) {
    case 1: backward_dot_k<1>(ic, r, y, rz); break;
    case 2: backward_dot_k<2>(ic, r, y, rz); break;
    case 3: backward_dot_k<3>(ic, r, y, rz); break;
    case 4: backward_dot_k<4>(ic, r, y, rz); break;
    default: assert(false);
  }
}

}  // namespace volspline::linalg::detail
