// SPDX-License-Identifier: MIT
#include "core/spline/grouped_gram.h"

#include <algorithm>
#include <cassert>
#include <utility>

#include <Eigen/Core>

namespace volspline::spline {

GroupedGram::GroupedGram(int n, int rhs_cols, std::vector<int> group_offsets, std::vector<int> group_cols)
    : n_(n), group_offsets_(std::move(group_offsets)), group_cols_(std::move(group_cols)) {
  assert(!group_offsets_.empty() && group_offsets_.front() == 0);
  assert(group_offsets_.back() == static_cast<int>(group_cols_.size()));
  const int groups = num_groups();
  // Groups holding each column.
  std::vector<int> holder_offsets(n + 1, 0), holders;
  for (int c : group_cols_) {
    assert(c >= 0 && c < n);
    ++holder_offsets[c + 1];
  }
  for (int i = 0; i < n; ++i) holder_offsets[i + 1] += holder_offsets[i];
  holders.resize(holder_offsets[n]);
  {
    std::vector<int> fill(holder_offsets.begin(), holder_offsets.end() - 1);
    for (int g = 0; g < groups; ++g) {
      assert(std::is_sorted(group_columns(g), group_columns(g) + group_size(g)));
      for (int q = group_offsets_[g]; q < group_offsets_[g + 1]; ++q) holders[fill[group_cols_[q]]++] = g;
    }
  }
  // Upper pattern: row i couples with every later column of every group holding i.
  std::vector<int> stamp(n, -1);
  offsets_.assign(1, 0);
  offsets_.reserve(n + 1);
  for (int i = 0; i < n; ++i) {
    const std::size_t first = cols_.size();
    cols_.push_back(i);
    stamp[i] = i;
    for (int h = holder_offsets[i]; h < holder_offsets[i + 1]; ++h) {
      const int g = holders[h];
      const int* begin = group_columns(g);
      const int* end = begin + group_size(g);
      for (const int* r = std::upper_bound(begin, end, i); r != end; ++r)
        if (stamp[*r] != i) {
          stamp[*r] = i;
          cols_.push_back(*r);
        }
    }
    std::sort(cols_.begin() + static_cast<std::ptrdiff_t>(first) + 1, cols_.end());
    offsets_.push_back(static_cast<int>(cols_.size()));
  }
  values_.assign(cols_.size(), 0.0);
  rhs_ = Eigen::MatrixXd::Zero(n, rhs_cols);
}

void GroupedGram::add(int g, const Eigen::MatrixXd& block, const Eigen::MatrixXd& t) {
  const int k = group_size(g);
  assert(block.cols() == k && t.rows() == block.rows() && t.cols() == rhs_.cols());
  if (block.rows() == 0 || k == 0) return;
  const int* gid = group_columns(g);
  // Lower triangle of blockᵀ block: column a holds the upper entries (a, b ≥ a) of row gid[a].
  local_gram_.setZero(k, k);
  local_gram_.selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
  local_rhs_.noalias() = block.transpose() * t;
  for (int a = 0; a < k; ++a) {
    const int i = gid[a];
    rhs_.row(i) += local_rhs_.row(a);
    // Merge of two sorted lists (gid[a..] ⊂ row i), skipping 8 columns at a time.
    int p = offsets_[i];
    const int end = offsets_[i + 1];
    const double* column = local_gram_.data() + static_cast<std::ptrdiff_t>(a) * k;
    values_[p] += column[a];  // the diagonal comes first
    ++p;
    for (int b = a + 1; b < k; ++b) {
      const int j = gid[b];
      while (p + 8 <= end && cols_[p + 7] < j) p += 8;
      while (cols_[p] < j) ++p;
      values_[p] += column[b];
    }
  }
}

linalg::CsrMatrix GroupedGram::take_symmetric() {
  // Row i of the full matrix: the mirrored entries (j, i), j < i, in increasing j, then row i of
  // the upper triangle (its diagonal first, so already in order).
  std::vector<int> counts(n_ + 1, 0);
  for (int i = 0; i < n_; ++i) {
    counts[i + 1] += offsets_[i + 1] - offsets_[i];
    for (int p = offsets_[i] + 1; p < offsets_[i + 1]; ++p) ++counts[cols_[p] + 1];
  }
  for (int i = 0; i < n_; ++i) counts[i + 1] += counts[i];
  std::vector<int> full_cols(counts[n_]);
  std::vector<double> full_values(counts[n_]);
  std::vector<int> fill(counts.begin(), counts.end() - 1);
  // Lower parts first: rows visited in increasing i give each row its lower entries in order.
  for (int i = 0; i < n_; ++i)
    for (int p = offsets_[i] + 1; p < offsets_[i + 1]; ++p) {
      const int j = cols_[p];
      full_cols[fill[j]] = i;
      full_values[fill[j]++] = values_[p];
    }
  for (int i = 0; i < n_; ++i)
    for (int p = offsets_[i]; p < offsets_[i + 1]; ++p) {
      full_cols[fill[i]] = cols_[p];
      full_values[fill[i]++] = values_[p];
    }
  values_.clear();
  return linalg::CsrMatrix::from_arrays(n_, n_, std::move(counts), std::move(full_cols), std::move(full_values));
}

linalg::CsrMatrix GroupedGram::take_upper() {
  return linalg::CsrMatrix::from_arrays(n_, n_, std::move(offsets_), std::move(cols_), std::move(values_));
}

}  // namespace volspline::spline
