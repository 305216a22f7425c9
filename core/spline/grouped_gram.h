// SPDX-License-Identifier: MIT
#pragma once

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
/// in a fixed order for deterministic sums), then take the matrix.
class GroupedGram {
 public:
  /// n: number of columns (unknowns); rhs_cols: columns of t. Group g has the columns
  /// group_cols[group_offsets[g] .. group_offsets[g+1]), strictly increasing, in [0, n)
  /// (asserted). The pattern is the union of the groups' blocks plus the whole diagonal.
  GroupedGram(int n, int rhs_cols, std::vector<int> group_offsets, std::vector<int> group_cols);

  /// Number of groups.
  int num_groups() const { return static_cast<int>(group_offsets_.size()) - 1; }
  /// Columns of group g (increasing) and their count.
  const int* group_columns(int g) const { return group_cols_.data() + group_offsets_[g]; }
  int group_size(int g) const { return group_offsets_[g + 1] - group_offsets_[g]; }

  /// Adds the rows `block` (r×k, k = group_size(g), column c ↔ group_columns(g)[c]) with right
  /// sides t (r×rhs_cols): MᵀM += blockᵀ block, Mᵀt += blockᵀ t.
  void add(int g, const Eigen::MatrixXd& block, const Eigen::MatrixXd& t);

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
  int n_ = 0;
  std::vector<int> group_offsets_, group_cols_;
  // Upper triangle, the diagonal first in each row, then increasing columns.
  std::vector<int> offsets_, cols_;
  std::vector<double> values_;
  Eigen::MatrixXd rhs_;
  Eigen::MatrixXd local_gram_, local_rhs_;
};

}  // namespace volspline::spline
