// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/linalg/csr_matrix.h"

namespace volspline::spline {

/// Normal equations MᵀM x = Mᵀt of a least-squares fit (Eq. 3.5/3.6) whose rows come in groups:
/// every row of a group is non-zero only on the group's column list (the blending functions of a
/// knot cell, or the union over a few neighbouring Eq. 4.7 rows). Each group adds one dense
/// Gram block (a symmetric rank update) into a sparse pattern fixed up front, far cheaper than
/// one sparse outer product per row when rows are long and share their columns.
///
/// Usage: construct with the groups' column lists, add() each group's rows (any number of times,
/// in a fixed order for deterministic sums) or add_all() every group's once, then take the matrix.
class GroupedGram {
 public:
  /// Writes the rows of group g: block (r×k, k = group_size(g)) and t (r×rhs_cols), resized by
  /// the callee. Called concurrently for different groups by add_all.
  using GroupRows = std::function<void(int g, Eigen::MatrixXd& block, Eigen::MatrixXd& t)>;

  /// n: number of columns (unknowns); rhs_cols: columns of t. Group g has the columns
  /// group_cols[group_offsets[g] .. group_offsets[g+1]), strictly increasing, in [0, n)
  /// (asserted). The pattern is the union of the groups' blocks plus the whole diagonal.
  /// threads (≥ 1): for the pattern and add_all; the result does not depend on it.
  GroupedGram(int n, int rhs_cols, std::vector<int> group_offsets, std::vector<int> group_cols, int threads = 1);

  /// Number of groups.
  int num_groups() const { return static_cast<int>(group_offsets_.size()) - 1; }
  /// Columns of group g (increasing) and their count.
  const int* group_columns(int g) const { return group_cols_.data() + group_offsets_[g]; }
  int group_size(int g) const { return group_offsets_[g + 1] - group_offsets_[g]; }

  /// Adds the rows `block` (r×k, k = group_size(g), column c ↔ group_columns(g)[c]) with right
  /// sides t (r×rhs_cols): MᵀM += blockᵀ block (a rank update), Mᵀt += blockᵀ t. Each entry
  /// gets one addition per call, so calls in a fixed order give fixed sums.
  void add(int g, const Eigen::MatrixXd& block, const Eigen::MatrixXd& t);
  /// Adds the rows of every group, rows(g, ...) for g = 0 .. num_groups() − 1, which writes
  /// row_counts[g] rows (asserted), in batches of consecutive groups: a batch's rows are formed
  /// in parallel (a group with at least as many rows as columns forms its Gram block at once);
  /// then each matrix row it touches is visited once, the Gram entries of every group holding
  /// it are formed and summed in group order into an accumulator, which is added to the row.
  /// The sums are fixed by the groups alone: the same bits for every thread count (they may
  /// differ from add() in the last bits). rows must be safe to call concurrently.
  void add_all(const std::vector<int>& row_counts, const GroupRows& rows);

  /// The right side Mᵀt, n×rhs_cols.
  const Eigen::MatrixXd& rhs() const { return rhs_; }
  Eigen::MatrixXd& rhs() { return rhs_; }

  /// MᵀM as an n×n CSR matrix with both triangles (sorted rows, the diagonal always stored);
  /// leaves this object without its matrix values.
  linalg::CsrMatrix take_symmetric();
  /// MᵀM as its upper triangle only (row i: the diagonal first, then columns > i increasing),
  /// what linalg::ConjugateGradient reads; leaves this object without its matrix.
  linalg::CsrMatrix take_upper();

 private:
  using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  // The rows of a batch of consecutive groups: group q's block (rows[q]×k, row-major) at
  // x[x_offset[q]], or with dense[q] set its Gram block there (k×k, lower triangle); its
  // blockᵀ t in rhs[q]; rows[q] = 0 adds nothing.
  struct Batch {
    std::vector<std::size_t> x_offset;
    std::vector<double> x;
    std::vector<int> rows;
    std::vector<char> dense;
    std::vector<Eigen::MatrixXd> rhs;
  };
  // Adds the batch of groups batch_begin .. batch_begin + count − 1, every matrix entry summed
  // in group order.
  void scatter_batch(int batch_begin, int count, const Batch& batch);

  int n_ = 0;
  int threads_ = 1;
  std::vector<int> group_offsets_, group_cols_;
  // Upper triangle, the diagonal first in each row, then increasing columns.
  std::vector<int> offsets_, cols_;
  std::vector<double> values_;
  Eigen::MatrixXd rhs_;
  // scatter_batch scratch: per row its number of pairs (zero between batches), the touched rows,
  // the (group in batch, column) pairs by row, and a dense accumulator (zero between rows) per
  // row range.
  std::vector<int> row_count_, touched_, pair_offsets_;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<std::vector<double>> accumulator_;
};

}  // namespace volspline::spline
