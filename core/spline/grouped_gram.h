// SPDX-License-Identifier: MIT
#pragma once

#include <functional>
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
  /// sides t (r×rhs_cols): MᵀM += blockᵀ block, Mᵀt += blockᵀ t.
  void add(int g, const Eigen::MatrixXd& block, const Eigen::MatrixXd& t);
  /// Adds the rows of every group, rows(g, ...) for g = 0 .. num_groups() − 1: bit for bit the
  /// sums of add(g, block, t) in increasing g, for every thread count (the dense blocks of a
  /// batch of groups are formed in parallel, then scattered by ranges of matrix rows, each
  /// entry still summed in group order). rows must be safe to call concurrently.
  void add_all(const GroupRows& rows);

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
  // Adds the lower triangle gram (k×k, column-major) and local_rhs (k×rhs_cols) of group g
  // to the matrix rows [row_begin, row_end).
  void scatter(int g, const double* gram, const Eigen::MatrixXd& local_rhs, int row_begin, int row_end);

  int n_ = 0;
  int threads_ = 1;
  std::vector<int> group_offsets_, group_cols_;
  // Upper triangle, the diagonal first in each row, then increasing columns.
  std::vector<int> offsets_, cols_;
  std::vector<double> values_;
  Eigen::MatrixXd rhs_;
  Eigen::MatrixXd local_gram_, local_rhs_;
};

}  // namespace volspline::spline
