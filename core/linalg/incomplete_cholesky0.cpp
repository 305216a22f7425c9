// SPDX-License-Identifier: MIT
#include "core/linalg/incomplete_cholesky0.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

#include "core/linalg/parallel_for.h"

namespace volspline::linalg {

namespace {

// Row-oriented (left-looking) IC(0) of A + shift·S on the pattern of `lower`, whose values hold
// the strictly lower entries of A on entry and of L on success. Returns false on a pivot ≤ 0.
bool factorize(const std::vector<double>& a_lower, const Eigen::VectorXd& diag,
               const Eigen::VectorXd& diag_scale, double shift, CsrMatrix& lower,
               Eigen::VectorXd& inverse_diagonal) {
  const int n = lower.rows();
  const int* off = lower.row_offsets().data();
  const int* col = lower.col_indices().data();
  std::vector<double>& l = lower.values();
  l = a_lower;
  // position_in_row[j] = index k of entry (i, j) of the current row i, valid if row_of[j] == i.
  std::vector<int> position_in_row(n, 0);
  std::vector<int> row_of(n, -1);
  for (int i = 0; i < n; ++i) {
    for (int k = off[i]; k < off[i + 1]; ++k) {
      position_in_row[col[k]] = k;
      row_of[col[k]] = i;
    }
    double pivot = diag[i] + shift * diag_scale[i];
    for (int k = off[i]; k < off[i + 1]; ++k) {
      const int c = col[k];
      // L_ic = (A_ic − Σ_{j<c} L_ij L_cj) / L_cc over the common pattern of rows i and c.
      double s = l[k];
      for (int t = off[c]; t < off[c + 1]; ++t) {
        const int j = col[t];
        if (row_of[j] == i) s -= l[position_in_row[j]] * l[t];
      }
      s *= inverse_diagonal[c];
      l[k] = s;
      pivot -= s * s;
    }
    if (!(pivot > 0.0) || !std::isfinite(pivot)) return false;
    inverse_diagonal[i] = 1.0 / std::sqrt(pivot);
  }
  return true;
}

}  // namespace

void IncompleteCholesky0::compute(const CsrMatrix& a) {
  assert(a.rows() == a.cols());
  const int n = a.rows();
  const std::vector<int>& a_off = a.row_offsets();
  const std::vector<int>& a_col = a.col_indices();
  const std::vector<double>& a_val = a.values();

  std::vector<int> offsets(n + 1, 0);
  std::vector<int> cols;
  std::vector<double> vals;
  Eigen::VectorXd diag = Eigen::VectorXd::Zero(n);
  cols.reserve(a.nnz() / 2 + 1);
  vals.reserve(a.nnz() / 2 + 1);
  for (int i = 0; i < n; ++i) {
    for (int k = a_off[i]; k < a_off[i + 1] && a_col[k] <= i; ++k) {
      if (a_col[k] == i) {
        diag[i] = a_val[k];
      } else {
        cols.push_back(a_col[k]);
        vals.push_back(a_val[k]);
      }
    }
    offsets[i + 1] = static_cast<int>(cols.size());
  }
  const std::vector<double> a_lower = vals;
  lower_ = CsrMatrix::from_arrays(n, n, std::move(offsets), std::move(cols), std::move(vals));
  Eigen::VectorXd diag_scale = diag.cwiseAbs();
  for (int i = 0; i < n; ++i) {
    if (diag_scale[i] == 0.0) diag_scale[i] = 1.0;
  }
  inverse_diagonal_.resize(n);

  // Attempt t uses shift 0 (t = 0), then 1e-3 doubled t − 1 times, t ≤ 60.
  constexpr int kAttempts = 61;
  auto shift_of = [](int attempt) { return attempt == 0 ? 0.0 : std::ldexp(1e-3, attempt - 1); };
  bool ok = false;
  if (threads_ <= 1) {
    for (int attempt = 0; !ok && attempt < kAttempts; ++attempt) {
      shift_ = shift_of(attempt);
      ok = factorize(a_lower, diag, diag_scale, shift_, lower_, inverse_diagonal_);
    }
  } else {
    // Rounds of `width` consecutive attempts run concurrently; the first success in attempt
    // order is the factor the sequential loop would keep.
    const int width = std::min(threads_, 4);
    std::vector<CsrMatrix> lower(static_cast<std::size_t>(width), lower_);
    std::vector<Eigen::VectorXd> inverse(static_cast<std::size_t>(width), inverse_diagonal_);
    std::vector<char> success(static_cast<std::size_t>(width));
    for (int first = 0; !ok && first < kAttempts; first += width) {
      const int count = std::min(width, kAttempts - first);
      parallel_for(threads_, count, [&](int w) {
        success[w] = factorize(a_lower, diag, diag_scale, shift_of(first + w), lower[w], inverse[w]);
      });
      for (int w = 0; w < count && !ok; ++w)
        if (success[w]) {
          ok = true;
          shift_ = shift_of(first + w);
          lower_ = std::move(lower[w]);
          inverse_diagonal_ = std::move(inverse[w]);
        }
    }
  }
  if (!ok) {
    shift_ = std::numeric_limits<double>::infinity();
    std::fill(lower_.values().begin(), lower_.values().end(), 0.0);
    inverse_diagonal_.setOnes();
  }
  upper_ = lower_.transpose();
}

namespace {

template <int K>
void solve_k(const CsrMatrix& lower, const CsrMatrix& upper, const double* inv,
             const double* const* r, double* const* z) {
  const int n = lower.rows();
  const int* lo = lower.row_offsets().data();
  const int* lc = lower.col_indices().data();
  const double* lv = lower.values().data();
  const int* uo = upper.row_offsets().data();
  const int* uc = upper.col_indices().data();
  const double* uv = upper.values().data();
  for (int i = 0; i < n; ++i) {
    double s[K];
    for (int c = 0; c < K; ++c) s[c] = r[c][i];
    for (int k = lo[i]; k < lo[i + 1]; ++k)
      for (int c = 0; c < K; ++c) s[c] -= lv[k] * z[c][lc[k]];
    for (int c = 0; c < K; ++c) z[c][i] = s[c] * inv[i];
  }
  for (int i = n - 1; i >= 0; --i) {
    double s[K];
    for (int c = 0; c < K; ++c) s[c] = z[c][i];
    for (int k = uo[i]; k < uo[i + 1]; ++k)
      for (int c = 0; c < K; ++c) s[c] -= uv[k] * z[c][uc[k]];
    for (int c = 0; c < K; ++c) z[c][i] = s[c] * inv[i];
  }
}

}  // namespace

void IncompleteCholesky0::solve(const double* r, double* z) const {
  solve_k<1>(lower_, upper_, inverse_diagonal_.data(), &r, &z);
}

void IncompleteCholesky0::solve_block(int k, const double* const* r, double* const* z) const {
  const double* inv = inverse_diagonal_.data();
  for (int first = 0; first < k; first += 4) {
    switch (std::min(4, k - first)) {
      case 1: solve(r[first], z[first]); break;
      case 2: solve_k<2>(lower_, upper_, inv, r + first, z + first); break;
      case 3: solve_k<3>(lower_, upper_, inv, r + first, z + first); break;
      default: solve_k<4>(lower_, upper_, inv, r + first, z + first); break;
    }
  }
}

Eigen::VectorXd IncompleteCholesky0::solve(const Eigen::VectorXd& r) const {
  assert(r.size() == lower_.rows());
  Eigen::VectorXd z(r.size());
  solve(r.data(), z.data());
  return z;
}

CsrMatrix IncompleteCholesky0::factor() const {
  const int n = lower_.rows();
  std::vector<Triplet> triplets;
  triplets.reserve(lower_.nnz() + n);
  for (int i = 0; i < n; ++i) {
    for (int k = lower_.row_offsets()[i]; k < lower_.row_offsets()[i + 1]; ++k) {
      triplets.push_back({i, lower_.col_indices()[k], lower_.values()[k]});
    }
    triplets.push_back({i, i, 1.0 / inverse_diagonal_[i]});
  }
  return CsrMatrix::from_triplets(n, n, triplets);
}

}  // namespace volspline::linalg
