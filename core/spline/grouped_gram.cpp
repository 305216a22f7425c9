// SPDX-License-Identifier: MIT
#include "core/spline/grouped_gram.h"

#include <algorithm>
#include <cassert>
#include <utility>

#include <Eigen/Core>

#include "core/linalg/parallel_for.h"

namespace volspline::spline {

namespace {

// Fixed work partitions (never derived from the thread count, so sums do not depend on it):
// matrix rows in up to kRowChunks ranges; groups in batches of at most kBatchGroups whose dense
// Gram blocks hold at most kBatchDoubles doubles (4 MiB, so that they are still cached when
// scattered) unless one group alone is larger.
constexpr int kRowChunks = 32;
constexpr int kBatchGroups = 512;
constexpr std::size_t kBatchDoubles = std::size_t(1) << 19;

}  // namespace

GroupedGram::GroupedGram(int n, int rhs_cols, std::vector<int> group_offsets, std::vector<int> group_cols, int threads)
    : n_(n), threads_(std::max(1, threads)), group_offsets_(std::move(group_offsets)), group_cols_(std::move(group_cols)) {
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
  // Upper pattern: row i couples with every later column of every group holding i. Rows are
  // independent, so fixed row ranges are built apart and concatenated in order.
  const int chunks = std::clamp(n / 256, 1, kRowChunks);
  std::vector<std::vector<int>> chunk_cols(static_cast<std::size_t>(chunks));
  std::vector<int> row_size(static_cast<std::size_t>(n));
  linalg::parallel_for(threads_, chunks, [&](int chunk) {
    const int row_begin = static_cast<int>(static_cast<long long>(n) * chunk / chunks);
    const int row_end = static_cast<int>(static_cast<long long>(n) * (chunk + 1) / chunks);
    std::vector<int> stamp(static_cast<std::size_t>(n), -1);
    std::vector<int>& cols = chunk_cols[chunk];
    for (int i = row_begin; i < row_end; ++i) {
      const std::size_t first = cols.size();
      cols.push_back(i);
      stamp[i] = i;
      for (int h = holder_offsets[i]; h < holder_offsets[i + 1]; ++h) {
        const int g = holders[h];
        const int* begin = group_columns(g);
        const int* end = begin + group_size(g);
        for (const int* r = std::upper_bound(begin, end, i); r != end; ++r)
          if (stamp[*r] != i) {
            stamp[*r] = i;
            cols.push_back(*r);
          }
      }
      std::sort(cols.begin() + static_cast<std::ptrdiff_t>(first) + 1, cols.end());
      row_size[i] = static_cast<int>(cols.size() - first);
    }
  });
  offsets_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int i = 0; i < n; ++i) offsets_[i + 1] = offsets_[i] + row_size[i];
  cols_.reserve(static_cast<std::size_t>(offsets_[n]));
  for (std::vector<int>& c : chunk_cols) {
    cols_.insert(cols_.end(), c.begin(), c.end());
    std::vector<int>().swap(c);
  }
  values_.assign(cols_.size(), 0.0);
  rhs_ = Eigen::MatrixXd::Zero(n, rhs_cols);
}

void GroupedGram::scatter(int g, const double* gram, const Eigen::MatrixXd& local_rhs, int row_begin, int row_end) {
  const int k = group_size(g);
  const int* gid = group_columns(g);
  const int a_begin = static_cast<int>(std::lower_bound(gid, gid + k, row_begin) - gid);
  const int a_end = static_cast<int>(std::lower_bound(gid + a_begin, gid + k, row_end) - gid);
  for (int a = a_begin; a < a_end; ++a) {
    const int i = gid[a];
    rhs_.row(i) += local_rhs.row(a);
    // Merge of two sorted lists (gid[a..] ⊂ row i), skipping 8 columns at a time.
    int p = offsets_[i];
    const int end = offsets_[i + 1];
    const double* column = gram + static_cast<std::ptrdiff_t>(a) * k;
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

void GroupedGram::add(int g, const Eigen::MatrixXd& block, const Eigen::MatrixXd& t) {
  const int k = group_size(g);
  assert(block.cols() == k && t.rows() == block.rows() && t.cols() == rhs_.cols());
  if (block.rows() == 0 || k == 0) return;
  // Lower triangle of blockᵀ block: column a holds the upper entries (a, b ≥ a) of row gid[a].
  local_gram_.setZero(k, k);
  local_gram_.selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
  local_rhs_.noalias() = block.transpose() * t;
  scatter(g, local_gram_.data(), local_rhs_, 0, n_);
}

void GroupedGram::add_all(const GroupRows& rows) {
  const int groups = num_groups();
  if (threads_ == 1) {
    // Each dense block scattered while it is still in cache.
    Eigen::MatrixXd block, t;
    for (int g = 0; g < groups; ++g) {
      rows(g, block, t);
      add(g, block, t);
    }
    return;
  }
  const int row_chunks = std::clamp(n_ / 256, 1, kRowChunks);
  std::vector<std::size_t> gram_offset;
  std::vector<double> grams;
  std::vector<Eigen::MatrixXd> rhs;
  std::vector<char> used;
  for (int batch_begin = 0; batch_begin < groups;) {
    // A batch: consecutive groups whose dense blocks fit the scratch budget (at least one).
    int batch_end = batch_begin;
    gram_offset.assign(1, 0);
    while (batch_end < groups && (batch_end == batch_begin || (batch_end - batch_begin < kBatchGroups &&
                                                              gram_offset.back() + static_cast<std::size_t>(group_size(batch_end)) * group_size(batch_end) <= kBatchDoubles))) {
      gram_offset.push_back(gram_offset.back() + static_cast<std::size_t>(group_size(batch_end)) * group_size(batch_end));
      ++batch_end;
    }
    const int count = batch_end - batch_begin;
    grams.resize(gram_offset.back());
    rhs.resize(static_cast<std::size_t>(count));
    used.assign(static_cast<std::size_t>(count), 0);
    linalg::parallel_for(threads_, count, [&](int q) {
      const int g = batch_begin + q;
      const int k = group_size(g);
      Eigen::MatrixXd block, t;
      rows(g, block, t);
      assert(block.cols() == k && t.rows() == block.rows() && t.cols() == rhs_.cols());
      if (block.rows() == 0 || k == 0) return;
      Eigen::Map<Eigen::MatrixXd> gram(grams.data() + gram_offset[q], k, k);
      // rankUpdate adds to, and scatter reads, the lower triangle only.
      for (int a = 0; a < k; ++a) gram.col(a).tail(k - a).setZero();
      gram.selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
      rhs[q].noalias() = block.transpose() * t;
      used[q] = 1;
    });
    linalg::parallel_for(threads_, row_chunks, [&](int chunk) {
      const int row_begin = static_cast<int>(static_cast<long long>(n_) * chunk / row_chunks);
      const int row_end = static_cast<int>(static_cast<long long>(n_) * (chunk + 1) / row_chunks);
      for (int q = 0; q < count; ++q)
        if (used[q]) scatter(batch_begin + q, grams.data() + gram_offset[q], rhs[q], row_begin, row_end);
    });
    batch_begin = batch_end;
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
