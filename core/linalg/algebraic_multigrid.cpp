// SPDX-License-Identifier: MIT
#include "core/linalg/algebraic_multigrid.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace volspline::linalg {

namespace {

// A stalled coarsening (no strong couplings left) larger than this ends in Gauss–Seidel sweeps
// instead of a dense factorization.
constexpr int kMaxDenseSize = 2000;
constexpr int kMaxLevels = 25;

// C = A B, rows in order, each entry summed over A's row then B's row in storage order.
CsrMatrix multiply(const CsrMatrix& a, const CsrMatrix& b) {
  const int rows = a.rows(), cols = b.cols();
  const int* ao = a.row_offsets().data();
  const int* ac = a.col_indices().data();
  const double* av = a.values().data();
  const int* bo = b.row_offsets().data();
  const int* bc = b.col_indices().data();
  const double* bv = b.values().data();
  std::vector<int> marker(cols, -1);
  std::vector<double> acc(cols, 0.0);
  std::vector<int> offsets(rows + 1, 0), out_cols, row_cols;
  std::vector<double> out_vals;
  out_cols.reserve(static_cast<std::size_t>(a.nnz()) * 2);
  out_vals.reserve(static_cast<std::size_t>(a.nnz()) * 2);
  for (int i = 0; i < rows; ++i) {
    row_cols.clear();
    for (int k = ao[i]; k < ao[i + 1]; ++k) {
      const int j = ac[k];
      const double v = av[k];
      for (int t = bo[j]; t < bo[j + 1]; ++t) {
        const int c = bc[t];
        if (marker[c] != i) {
          marker[c] = i;
          acc[c] = 0.0;
          row_cols.push_back(c);
        }
        acc[c] += v * bv[t];
      }
    }
    std::sort(row_cols.begin(), row_cols.end());
    for (int c : row_cols) {
      out_cols.push_back(c);
      out_vals.push_back(acc[c]);
    }
    offsets[i + 1] = static_cast<int>(out_cols.size());
  }
  return CsrMatrix::from_arrays(rows, cols, std::move(offsets), std::move(out_cols), std::move(out_vals));
}

// (A + Aᵀ) / 2 for a matrix with a symmetric pattern (Pᵀ A P of a symmetric A): removes the
// rounding asymmetry of the triple product so that the V-cycle stays a symmetric operator.
void symmetrize(CsrMatrix& a) {
  const CsrMatrix t = a.transpose();
  if (t.row_offsets() != a.row_offsets() || t.col_indices() != a.col_indices()) return;
  std::vector<double>& v = a.values();
  for (std::size_t k = 0; k < v.size(); ++k) v[k] = 0.5 * (v[k] + t.values()[k]);
}

// Aggregates of the strong-coupling graph (Vaněk et al. 1996, §5): per node its aggregate or
// −1 (a node without strong couplings stays out: Gauss–Seidel alone resolves it). Returns the
// number of aggregates.
int aggregate(const CsrMatrix& a, const std::vector<char>& strong, std::vector<int>& agg) {
  const int n = a.rows();
  const int* off = a.row_offsets().data();
  const int* col = a.col_indices().data();
  const double* val = a.values().data();
  agg.assign(n, -1);
  int count = 0;
  // 1: a node whose strong neighbours are all free seeds an aggregate with them.
  for (int i = 0; i < n; ++i) {
    if (agg[i] >= 0) continue;
    bool neighbours = false, free = true;
    for (int k = off[i]; k < off[i + 1] && free; ++k) {
      if (!strong[k]) continue;
      neighbours = true;
      free = agg[col[k]] < 0;
    }
    if (!neighbours || !free) continue;
    agg[i] = count;
    for (int k = off[i]; k < off[i + 1]; ++k)
      if (strong[k]) agg[col[k]] = count;
    ++count;
  }
  // 2: a free node joins the aggregate of its strongest aggregated neighbour (of step 1).
  std::vector<int> joined(n, -1);
  for (int i = 0; i < n; ++i) {
    if (agg[i] >= 0) continue;
    double best = 0.0;
    for (int k = off[i]; k < off[i + 1]; ++k)
      if (strong[k] && agg[col[k]] >= 0 && std::abs(val[k]) > best) {
        best = std::abs(val[k]);
        joined[i] = agg[col[k]];
      }
  }
  for (int i = 0; i < n; ++i)
    if (joined[i] >= 0) agg[i] = joined[i];
  // 3: the nodes still free form aggregates with their free strong neighbours.
  for (int i = 0; i < n; ++i) {
    if (agg[i] >= 0) continue;
    bool neighbours = false;
    for (int k = off[i]; k < off[i + 1]; ++k) neighbours = neighbours || strong[k];
    if (!neighbours) continue;
    agg[i] = count;
    for (int k = off[i]; k < off[i + 1]; ++k)
      if (strong[k] && agg[col[k]] < 0) agg[col[k]] = count;
    ++count;
  }
  return count;
}

// Smoothed prolongator P = (I − ω D_F⁻¹ A_F) P̂ (Vaněk et al. 1996, §3): P̂ is 1 at (i, agg(i)),
// A_F keeps the strong couplings and lumps the weak ones into its diagonal D_F.
CsrMatrix smoothed_prolongation(const CsrMatrix& a, const std::vector<char>& strong, const std::vector<int>& agg,
                                int num_aggregates) {
  const int n = a.rows();
  const int* off = a.row_offsets().data();
  const int* col = a.col_indices().data();
  const double* val = a.values().data();
  std::vector<double> filtered_diagonal(n, 0.0);
  double rho = 0.0;  // Gershgorin bound of ρ(D_F⁻¹ A_F)
  for (int i = 0; i < n; ++i) {
    double d = 0.0, weak = 0.0, off_sum = 0.0;
    for (int k = off[i]; k < off[i + 1]; ++k) {
      if (col[k] == i)
        d = val[k];
      else if (strong[k])
        off_sum += std::abs(val[k]);
      else
        weak += val[k];
    }
    double df = d + weak;
    if (!(df > 0.0)) df = d > 0.0 ? d : 1.0;
    filtered_diagonal[i] = df;
    rho = std::max(rho, (df + off_sum) / df);
  }
  const double omega = 4.0 / (3.0 * std::max(rho, 1.0));
  std::vector<int> marker(num_aggregates, -1);
  std::vector<double> acc(num_aggregates, 0.0);
  std::vector<int> offsets(n + 1, 0), out_cols, row_cols;
  std::vector<double> out_vals;
  out_cols.reserve(static_cast<std::size_t>(a.nnz()));
  out_vals.reserve(static_cast<std::size_t>(a.nnz()));
  auto add = [&](int i, int c, double v) {
    if (marker[c] != i) {
      marker[c] = i;
      acc[c] = 0.0;
      row_cols.push_back(c);
    }
    acc[c] += v;
  };
  for (int i = 0; i < n; ++i) {
    row_cols.clear();
    const double scale = omega / filtered_diagonal[i];
    if (agg[i] >= 0) add(i, agg[i], 1.0 - omega);
    for (int k = off[i]; k < off[i + 1]; ++k)
      if (col[k] != i && strong[k] && agg[col[k]] >= 0) add(i, agg[col[k]], -scale * val[k]);
    std::sort(row_cols.begin(), row_cols.end());
    for (int c : row_cols) {
      out_cols.push_back(c);
      out_vals.push_back(acc[c]);
    }
    offsets[i + 1] = static_cast<int>(out_cols.size());
  }
  return CsrMatrix::from_arrays(n, num_aggregates, std::move(offsets), std::move(out_cols), std::move(out_vals));
}

template <int K>
void gauss_seidel(const CsrMatrix& a, const double* inv, const double* const* b, double* const* x, bool forward) {
  const int n = a.rows();
  const int* off = a.row_offsets().data();
  const int* col = a.col_indices().data();
  const double* val = a.values().data();
  for (int step = 0; step < n; ++step) {
    const int i = forward ? step : n - 1 - step;
    double s[K];
    for (int c = 0; c < K; ++c) s[c] = b[c][i];
    for (int k = off[i]; k < off[i + 1]; ++k) {
      const int j = col[k];
      const double v = val[k];
      for (int c = 0; c < K; ++c) s[c] -= v * x[c][j];
    }
    for (int c = 0; c < K; ++c) x[c][i] += s[c] * inv[i];
  }
}

}  // namespace

void AlgebraicMultigrid::compute(const CsrMatrix& a) {
  assert(a.rows() == a.cols());
  levels_.clear();
  CsrMatrix current = a;
  double theta = 0.08;
  while (current.rows() > kCoarseSize && static_cast<int>(levels_.size()) < kMaxLevels) {
    const int n = current.rows();
    const int* off = current.row_offsets().data();
    const int* col = current.col_indices().data();
    const double* val = current.values().data();
    Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < n; ++i)
      for (int k = off[i]; k < off[i + 1]; ++k)
        if (col[k] == i) diagonal[i] = val[k];
    std::vector<char> strong(current.nnz(), 0);
    for (int i = 0; i < n; ++i)
      for (int k = off[i]; k < off[i + 1]; ++k) {
        const int j = col[k];
        if (j != i && val[k] != 0.0)
          strong[k] = std::abs(val[k]) >= theta * std::sqrt(std::abs(diagonal[i] * diagonal[j]));
      }
    std::vector<int> agg;
    const int num_aggregates = aggregate(current, strong, agg);
    Level level;
    level.inverse_diagonal.resize(n);
    for (int i = 0; i < n; ++i) level.inverse_diagonal[i] = diagonal[i] > 0.0 ? 1.0 / diagonal[i] : 1.0;
    if (num_aggregates == 0 || num_aggregates > 0.9 * n) {
      // No coarsening left: dense if small enough, else symmetric Gauss–Seidel alone.
      if (n <= kMaxDenseSize) break;
      level.prolongation = CsrMatrix::from_arrays(n, 0, std::vector<int>(n + 1, 0), {}, {});
      level.a = std::move(current);
      levels_.push_back(std::move(level));
      current = CsrMatrix();
      break;
    }
    level.prolongation = smoothed_prolongation(current, strong, agg, num_aggregates);
    CsrMatrix coarse = multiply(level.prolongation.transpose(), multiply(current, level.prolongation));
    symmetrize(coarse);
    level.a = std::move(current);
    levels_.push_back(std::move(level));
    current = std::move(coarse);
    theta *= 0.5;
  }
  coarse_size_ = current.rows();
  coarse_nnz_ = coarse_size_ * coarse_size_;
  if (coarse_size_ > 0) coarse_.compute(current.to_dense());
  b_.assign(levels_.size(), Eigen::MatrixXd());
  x_.assign(levels_.size(), Eigen::MatrixXd());
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    b_[l].resize(levels_[l].prolongation.cols(), 4);
    x_[l].resize(levels_[l].prolongation.cols(), 4);
  }
}

int AlgebraicMultigrid::level_size(int level) const {
  assert(level >= 0 && level < num_levels());
  return level < static_cast<int>(levels_.size()) ? levels_[level].a.rows() : coarse_size_;
}

double AlgebraicMultigrid::operator_complexity() const {
  const double first = levels_.empty() ? double(coarse_nnz_) : double(levels_[0].a.nnz());
  if (!(first > 0.0)) return 1.0;
  double total = coarse_nnz_;
  for (const Level& l : levels_) total += l.a.nnz();
  return total / first;
}

// §3 of Vaněk et al.: pre-smoothing, coarse-grid correction with Pᵀ and P, post-smoothing in
// the reverse order, so that the cycle is symmetric.
template <int K>
void AlgebraicMultigrid::cycle(int level, const double* const* b, double* const* x) const {
  if (level == static_cast<int>(levels_.size())) {
    if (coarse_size_ == 0) return;
    for (int c = 0; c < K; ++c)
      Eigen::Map<Eigen::VectorXd>(x[c], coarse_size_) =
          coarse_.solve(Eigen::Map<const Eigen::VectorXd>(b[c], coarse_size_));
    return;
  }
  const Level& l = levels_[level];
  const int n = l.a.rows();
  const int* off = l.a.row_offsets().data();
  const int* col = l.a.col_indices().data();
  const double* val = l.a.values().data();
  const double* inv = l.inverse_diagonal.data();
  // Forward sweep from x = 0: only the columns left of the diagonal contribute.
  for (int i = 0; i < n; ++i) {
    double s[K];
    for (int c = 0; c < K; ++c) s[c] = b[c][i];
    for (int k = off[i]; k < off[i + 1] && col[k] < i; ++k) {
      const int j = col[k];
      const double v = val[k];
      for (int c = 0; c < K; ++c) s[c] -= v * x[c][j];
    }
    for (int c = 0; c < K; ++c) x[c][i] = s[c] * inv[i];
  }
  const int nc = l.prolongation.cols();
  if (nc > 0) {
    const int* po = l.prolongation.row_offsets().data();
    const int* pc = l.prolongation.col_indices().data();
    const double* pv = l.prolongation.values().data();
    double* bc[K];
    double* xc[K];
    for (int c = 0; c < K; ++c) {
      bc[c] = b_[level].col(c).data();
      xc[c] = x_[level].col(c).data();
      std::fill(bc[c], bc[c] + nc, 0.0);
    }
    // Residual, restricted by Pᵀ as it is formed.
    for (int i = 0; i < n; ++i) {
      double s[K];
      for (int c = 0; c < K; ++c) s[c] = b[c][i];
      for (int k = off[i]; k < off[i + 1]; ++k) {
        const int j = col[k];
        const double v = val[k];
        for (int c = 0; c < K; ++c) s[c] -= v * x[c][j];
      }
      for (int t = po[i]; t < po[i + 1]; ++t)
        for (int c = 0; c < K; ++c) bc[c][pc[t]] += pv[t] * s[c];
    }
    cycle<K>(level + 1, bc, xc);
    for (int i = 0; i < n; ++i)
      for (int t = po[i]; t < po[i + 1]; ++t)
        for (int c = 0; c < K; ++c) x[c][i] += pv[t] * xc[c][pc[t]];
  }
  gauss_seidel<K>(l.a, inv, b, x, false);
}

template <int K>
void AlgebraicMultigrid::solve_k(const double* const* r, double* const* z) const {
  bool alias = false;
  for (int c = 0; c < K; ++c) alias = alias || r[c] == z[c];
  const int n = level_size(0);
  if (!alias) {
    cycle<K>(0, r, z);
    return;
  }
  input_.resize(n, K);
  const double* copy[K];
  for (int c = 0; c < K; ++c) {
    std::copy(r[c], r[c] + n, input_.col(c).data());
    copy[c] = input_.col(c).data();
  }
  cycle<K>(0, copy, z);
}

void AlgebraicMultigrid::solve(const double* r, double* z) const { solve_k<1>(&r, &z); }

void AlgebraicMultigrid::solve_block(int k, const double* const* r, double* const* z) const {
  for (int first = 0; first < k; first += 4) {
    switch (std::min(4, k - first)) {
      case 1: solve_k<1>(r + first, z + first); break;
      case 2: solve_k<2>(r + first, z + first); break;
      case 3: solve_k<3>(r + first, z + first); break;
      default: solve_k<4>(r + first, z + first); break;
    }
  }
}

Eigen::VectorXd AlgebraicMultigrid::solve(const Eigen::VectorXd& r) const {
  assert(r.size() == level_size(0));
  Eigen::VectorXd z(r.size());
  solve(r.data(), z.data());
  return z;
}

}  // namespace volspline::linalg
