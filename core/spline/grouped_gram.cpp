// SPDX-License-Identifier: MIT
#include "core/spline/grouped_gram.h"

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <utility>

#include <Eigen/Core>

#include "core/linalg/parallel_for.h"

namespace volspline::spline {

namespace {

// Fixed work partitions (never derived from the thread count, so sums do not depend on it):
// groups in batches of at most kBatchGroups whose rows hold at most kBatchDoubles doubles
// (512 KiB, about a level-2 cache, so that they stay cached while the matrix rows are visited)
// unless one group alone is larger; the pattern in up to kRowChunks ranges of rows.
constexpr int kRowChunks = 32;
constexpr int kBatchGroups = 1024;
constexpr std::size_t kBatchDoubles = std::size_t(1) << 16;

// A group with at least as many rows as columns, and more than a level-1 cache of them, stores
// its Gram block (formed once by a rank update) instead of its rows: a column formed from rows
// out of cache would cost more than reading it.
bool dense_gram(std::size_t rows, std::size_t k) { return rows * k > 2048 && rows >= k; }

// Entries a .. k−1 of column a of XᵀX (X: rows×k, row-major) into out[0 .. k−a): four rows at a
// time, so each pass over out does eight multiply-adds per entry loaded and stored. On x86-64
// an AVX2 clone is chosen at run time: the loop over out vectorizes with the same operations
// per entry (AVX2 without FMA, no reassociation), so both give the same bits.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__EMSCRIPTEN__)
__attribute__((target_clones("avx2", "default")))
#endif
void gram_column(const double* x, int rows, int k, int a, double* __restrict out) {
  const int len = k - a;
  std::fill(out, out + len, 0.0);
  int r = 0;
  for (; r + 4 <= rows; r += 4) {
    const double* __restrict x0 = x + static_cast<std::ptrdiff_t>(r) * k + a;
    const double* __restrict x1 = x0 + k;
    const double* __restrict x2 = x1 + k;
    const double* __restrict x3 = x2 + k;
    const double c0 = x0[0], c1 = x1[0], c2 = x2[0], c3 = x3[0];
    for (int b = 0; b < len; ++b) out[b] += (c0 * x0[b] + c1 * x1[b]) + (c2 * x2[b] + c3 * x3[b]);
  }
  for (; r < rows; ++r) {
    const double* __restrict xr = x + static_cast<std::ptrdiff_t>(r) * k + a;
    const double c = xr[0];
    for (int b = 0; b < len; ++b) out[b] += c * xr[b];
  }
}

}  // namespace

GroupedGram::GroupedGram(int n, int rhs_cols, std::vector<int> group_offsets, std::vector<int> group_cols, int threads)
    : n_(n), threads_(std::max(1, threads)), group_offsets_(std::move(group_offsets)), group_cols_(std::move(group_cols)) {
  assert(!group_offsets_.empty() && group_offsets_.front() == 0);
  assert(group_offsets_.back() == static_cast<int>(group_cols_.size()));
  const int groups = num_groups();
  const int chunks = std::clamp(n / 256, 1, kRowChunks);
  std::vector<std::vector<int>> chunk_cols(static_cast<std::size_t>(chunks));
  std::vector<int> row_size(static_cast<std::size_t>(n));
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
  linalg::parallel_for(threads_, chunks, [&](int chunk) {
    const int row_begin = static_cast<int>(static_cast<long long>(n) * chunk / chunks);
    const int row_end = static_cast<int>(static_cast<long long>(n) * (chunk + 1) / chunks);
    // The columns after i of every group holding i, as bits (set in any order, read out
    // increasing: no sort); the words between the row's least and largest column are read.
    std::vector<std::uint64_t> bits(static_cast<std::size_t>(n) / 64 + 1, 0);
    std::vector<int>& cols = chunk_cols[chunk];
    const int* group_cols = group_cols_.data();
    for (int i = row_begin; i < row_end; ++i) {
      int least = n, largest = -1;
      for (int h = holder_offsets[i]; h < holder_offsets[i + 1]; ++h) {
        const int g = holders[h];
        const int* end = group_cols + group_offsets_[g + 1];
        const int* p = std::upper_bound(group_cols + group_offsets_[g], end, i);
        if (p == end) continue;
        least = std::min(least, *p);
        largest = std::max(largest, *(end - 1));
        for (; p != end; ++p) bits[static_cast<std::size_t>(*p) >> 6] |= std::uint64_t(1) << (*p & 63);
      }
      cols.push_back(i);
      std::size_t count = 0;
      for (int word = least >> 6; word <= (largest >> 6); ++word) {
        std::uint64_t b = bits[static_cast<std::size_t>(word)];
        bits[static_cast<std::size_t>(word)] = 0;
        while (b) {
          cols.push_back(word * 64 + __builtin_ctzll(b));
          b &= b - 1;
          ++count;
        }
      }
      row_size[i] = static_cast<int>(count) + 1;
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
  row_count_.assign(static_cast<std::size_t>(n), 0);
}

void GroupedGram::scatter_batch(int batch_begin, int count, const Batch& batch) {
  // The (group in batch, column) pairs by matrix row, each row's pairs in group order.
  touched_.clear();
  for (int q = 0; q < count; ++q) {
    if (batch.rows[q] == 0) continue;
    const int g = batch_begin + q;
    for (int a = 0, k = group_size(g); a < k; ++a) {
      const int i = group_columns(g)[a];
      if (row_count_[i]++ == 0) touched_.push_back(i);
    }
  }
  std::sort(touched_.begin(), touched_.end());
  const int rows = static_cast<int>(touched_.size());
  pair_offsets_.resize(static_cast<std::size_t>(rows) + 1);
  pair_offsets_[0] = 0;
  for (int r = 0; r < rows; ++r) {
    const int i = touched_[r];
    pair_offsets_[r + 1] = pair_offsets_[r] + row_count_[i];
    row_count_[i] = pair_offsets_[r];  // now the fill position
  }
  pairs_.resize(static_cast<std::size_t>(pair_offsets_[rows]));
  for (int q = 0; q < count; ++q) {
    if (batch.rows[q] == 0) continue;
    const int g = batch_begin + q;
    for (int a = 0, k = group_size(g); a < k; ++a) pairs_[row_count_[group_columns(g)[a]]++] = {q, a};
  }
  for (int i : touched_) row_count_[i] = 0;
  // Fixed ranges of matrix rows, apart: the pairs of row i (in group order) form their Gram
  // columns and add them to a dense accumulator indexed by column, which is then added to the
  // row's entries (walking its columns clears it again), so each entry's sum has a fixed order.
  // Rows are independent, so the ranges may follow the thread count (one accumulator per range).
  const int row_chunks = threads_ == 1 ? 1 : std::min(4 * threads_, kRowChunks);
  if (accumulator_.size() < static_cast<std::size_t>(row_chunks)) accumulator_.resize(static_cast<std::size_t>(row_chunks));
  linalg::parallel_for(threads_, row_chunks, [&](int chunk) {
    const int row_begin = static_cast<int>(static_cast<long long>(n_) * chunk / row_chunks);
    const int row_end = static_cast<int>(static_cast<long long>(n_) * (chunk + 1) / row_chunks);
    const int first = static_cast<int>(std::lower_bound(touched_.begin(), touched_.end(), row_begin) - touched_.begin());
    if (first == rows || touched_[first] >= row_end) return;
    std::vector<double>& accumulator = accumulator_[chunk];
    if (accumulator.empty()) accumulator.assign(static_cast<std::size_t>(n_), 0.0);
    double* __restrict acc = accumulator.data();
    std::vector<double> column;
    for (int r = first; r < rows && touched_[r] < row_end; ++r) {
      const int i = touched_[r];
      for (int e = pair_offsets_[r]; e < pair_offsets_[r + 1]; ++e) {
        const auto [q, a] = pairs_[e];
        const int g = batch_begin + q;
        const int k = group_size(g);
        const int* __restrict gid = group_columns(g) + a;
        const double* col;
        if (batch.dense[q]) {
          col = batch.x.data() + batch.x_offset[q] + static_cast<std::size_t>(a) * k + a;
        } else {
          column.resize(static_cast<std::size_t>(k));
          gram_column(batch.x.data() + batch.x_offset[q], batch.rows[q], k, a, column.data());
          col = column.data();
        }
        rhs_.row(i) += batch.rhs[q].row(a);
        for (int b = 0; b < k - a; ++b) acc[gid[b]] += col[b];
      }
      double* __restrict values = values_.data();
      const int* __restrict cols = cols_.data();
      for (int p = offsets_[i]; p < offsets_[i + 1]; ++p) {
        values[p] += acc[cols[p]];
        acc[cols[p]] = 0.0;
      }
    }
  });
}

void GroupedGram::add(int g, const Eigen::MatrixXd& block, const Eigen::MatrixXd& t) {
  const int k = group_size(g);
  assert(block.cols() == k && t.rows() == block.rows() && t.cols() == rhs_.cols());
  if (block.rows() == 0 || k == 0) return;
  // The Gram block by a rank update (its lower triangle), each entry then added on its own.
  Batch batch;
  batch.x.assign(static_cast<std::size_t>(k) * k, 0.0);
  Eigen::Map<Eigen::MatrixXd>(batch.x.data(), k, k).selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
  batch.x_offset = {0};
  batch.rows = {static_cast<int>(block.rows())};
  batch.dense = {1};
  batch.rhs.resize(1);
  batch.rhs[0].noalias() = block.transpose() * t;
  scatter_batch(g, 1, batch);
}

void GroupedGram::add_all(const std::vector<int>& row_counts, const GroupRows& rows) {
  const int groups = num_groups();
  assert(static_cast<int>(row_counts.size()) == groups);
  Batch batch;
  for (int batch_begin = 0; batch_begin < groups;) {
    // A batch: consecutive groups whose rows fit the scratch budget (at least one).
    int batch_end = batch_begin;
    batch.x_offset.assign(1, 0);
    auto size = [&](int g) {
      const std::size_t k = static_cast<std::size_t>(group_size(g)), r = static_cast<std::size_t>(row_counts[g]);
      return dense_gram(r, k) ? k * k : r * k;
    };
    while (batch_end < groups && (batch_end == batch_begin || (batch_end - batch_begin < kBatchGroups &&
                                                              batch.x_offset.back() + size(batch_end) <= kBatchDoubles))) {
      batch.x_offset.push_back(batch.x_offset.back() + size(batch_end));
      ++batch_end;
    }
    const int count = batch_end - batch_begin;
    batch.x.resize(batch.x_offset.back());
    batch.rhs.resize(static_cast<std::size_t>(count));
    batch.rows.assign(static_cast<std::size_t>(count), 0);
    batch.dense.assign(static_cast<std::size_t>(count), 0);
    linalg::parallel_for(threads_, count, [&](int q) {
      const int g = batch_begin + q;
      const int k = group_size(g);
      Eigen::MatrixXd block, t;
      rows(g, block, t);
      assert(block.cols() == k && block.rows() == row_counts[g] && t.rows() == block.rows() && t.cols() == rhs_.cols());
      if (block.rows() == 0 || k == 0) return;
      if (dense_gram(static_cast<std::size_t>(block.rows()), static_cast<std::size_t>(k))) {
        // Many rows: the Gram block itself, formed once (its lower triangle: column a holds
        // entries (a, b ≥ a)) instead of its columns one at a time from rows out of cache.
        Eigen::Map<Eigen::MatrixXd> gram(batch.x.data() + batch.x_offset[q], k, k);
        for (int a = 0; a < k; ++a) gram.col(a).tail(k - a).setZero();
        gram.selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
        batch.dense[q] = 1;
      } else {
        Eigen::Map<RowMajorMatrix>(batch.x.data() + batch.x_offset[q], block.rows(), k) = block;
      }
      batch.rhs[q].noalias() = block.transpose() * t;
      batch.rows[q] = static_cast<int>(block.rows());
    });
    scatter_batch(batch_begin, count, batch);
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
