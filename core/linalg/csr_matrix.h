// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "core/linalg/triplet.h"

namespace volspline::linalg {

/// Sparse matrix in compressed sparse row form.
///
/// Layout: row i owns entries [row_offsets()[i], row_offsets()[i+1]) of col_indices() and
/// values(); columns inside a row are strictly increasing. Explicit zeros that come from the
/// triplets (including duplicates summing to zero) are kept, so the pattern only depends on
/// the triplet indices.
///
/// Vector convention: every product takes Eigen vectors (Eigen::Ref, so columns of an n×k
/// matrix work without copies); the hot loops underneath work on raw pointers.
class CsrMatrix {
 public:
  /// Empty 0×0 matrix.
  CsrMatrix() = default;

  /// Builds a rows×cols matrix from triplets; duplicates are summed in input order, so the
  /// result is deterministic. Throws volspline::Error naming the triplet index if a row or
  /// column is out of range or a value is NaN/Inf, or if rows/cols is negative.
  static CsrMatrix from_triplets(int rows, int cols, const std::vector<Triplet>& triplets);

  /// Builds from raw CSR arrays (row_offsets has rows+1 entries, starting at 0, non-decreasing;
  /// columns strictly increasing in each row and < cols). Throws volspline::Error otherwise.
  static CsrMatrix from_arrays(int rows, int cols, std::vector<int> row_offsets,
                               std::vector<int> col_indices, std::vector<double> values);

  /// Copies an Eigen sparse matrix (any storage order); explicit zeros stored in it are kept.
  static CsrMatrix from_eigen(const Eigen::SparseMatrix<double, Eigen::RowMajor>& a);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  /// Number of stored entries.
  int nnz() const { return static_cast<int>(values_.size()); }

  /// rows()+1 offsets into col_indices()/values().
  const std::vector<int>& row_offsets() const { return row_offsets_; }
  /// nnz() column indices, increasing within each row.
  const std::vector<int>& col_indices() const { return col_indices_; }
  /// nnz() values, same order as col_indices().
  const std::vector<double>& values() const { return values_; }
  /// Mutable values (the pattern stays fixed), e.g. to reassemble with new weights.
  std::vector<double>& values() { return values_; }

  /// Entry (row, col), 0 if not stored. Binary search in the row: O(log row length).
  double coeff(int row, int col) const;

  /// y = A x. x has cols() entries, y has rows() entries; x and y must not alias.
  void multiply(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> y) const;
  /// y += alpha A x. Same shapes as multiply.
  void multiply_add(double alpha, const Eigen::Ref<const Eigen::VectorXd>& x,
                    Eigen::Ref<Eigen::VectorXd> y) const;
  /// Returns A x (allocates the result).
  Eigen::VectorXd operator*(const Eigen::VectorXd& x) const;

  /// min(rows, cols) diagonal entries (0 where not stored).
  Eigen::VectorXd diagonal() const;

  /// Aᵀ as a new CSR matrix (cols×rows); O(nnz + rows + cols).
  CsrMatrix transpose() const;

  /// Copy as an Eigen sparse matrix (row-major, same pattern including explicit zeros).
  Eigen::SparseMatrix<double, Eigen::RowMajor> to_eigen() const;

  /// Dense copy, for tests and tiny systems.
  Eigen::MatrixXd to_dense() const;

 private:
  int rows_ = 0;
  int cols_ = 0;
  std::vector<int> row_offsets_ = {0};
  std::vector<int> col_indices_;
  std::vector<double> values_;
};

/// AᵀA (cols×cols, symmetric, full pattern stored) for an m×n matrix A. Deterministic: each
/// entry is summed over the rows of A in increasing order.
CsrMatrix transpose_times_self(const CsrMatrix& a);

/// The normal equations AᵀA x = Aᵀb of the least-squares problem min ‖A x − b‖.
struct NormalEquations {
  CsrMatrix ata;        ///< n×n, symmetric positive semi-definite
  Eigen::MatrixXd atb;  ///< n×k, one column per right-hand side
};

/// Forms AᵀA and AᵀB for an m×n matrix A and an m×k right-hand side B (k columns, e.g. the
/// three coordinates of a fit). Asserts B has m rows.
NormalEquations normal_equations(const CsrMatrix& a, const Eigen::MatrixXd& b);

/// Weighted variant: AᵀWA and AᵀWB with W = diag(weights), weights has m entries (≥ 0).
NormalEquations normal_equations(const CsrMatrix& a, const Eigen::MatrixXd& b,
                                 const Eigen::VectorXd& weights);

}  // namespace volspline::linalg
