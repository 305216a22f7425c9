// SPDX-License-Identifier: MIT
#include "core/linalg/csr_matrix.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

#include "core/common/error.h"

namespace volspline::linalg {

namespace {

// Shared kernel of multiply/multiply_add: y = beta*y + alpha*A x, gathered row by row.
void spmv(const CsrMatrix& a, double alpha, const double* x, double beta, double* y) {
  const int* offsets = a.row_offsets().data();
  const int* cols = a.col_indices().data();
  const double* vals = a.values().data();
  const int rows = a.rows();
  for (int i = 0; i < rows; ++i) {
    double sum = 0.0;
    for (int k = offsets[i]; k < offsets[i + 1]; ++k) sum += vals[k] * x[cols[k]];
    y[i] = (beta == 0.0 ? 0.0 : beta * y[i]) + alpha * sum;
  }
}

NormalEquations normal_equations_impl(const CsrMatrix& a, const Eigen::MatrixXd& b,
                                      const double* weights) {
  assert(b.rows() == a.rows());
  const int n = a.cols();
  const CsrMatrix at = a.transpose();
  const std::vector<int>& a_off = a.row_offsets();
  const std::vector<int>& a_col = a.col_indices();
  const std::vector<double>& a_val = a.values();
  const std::vector<int>& t_off = at.row_offsets();
  const std::vector<int>& t_col = at.col_indices();
  const std::vector<double>& t_val = at.values();

  // Gustavson's row-by-row product (AᵀW)A with a dense accumulator, upper triangle only (one
  // product per pair), then mirrored. Entries of row i are summed over k = rows of A in
  // increasing order, so the result is deterministic and exactly symmetric.
  std::vector<int> upper_offsets(n + 1, 0);
  std::vector<int> upper_cols;
  std::vector<double> upper_vals;
  std::vector<double> accumulator(n, 0.0);
  std::vector<int> marker(n, -1);
  std::vector<int> row_cols;
  for (int i = 0; i < n; ++i) {
    row_cols.clear();
    for (int t = t_off[i]; t < t_off[i + 1]; ++t) {
      const int k = t_col[t];
      const double w = t_val[t] * (weights ? weights[k] : 1.0);
      for (int s = a_off[k]; s < a_off[k + 1]; ++s) {
        const int j = a_col[s];
        if (j < i) continue;
        if (marker[j] != i) {
          marker[j] = i;
          accumulator[j] = 0.0;
          row_cols.push_back(j);
        }
        accumulator[j] += w * a_val[s];
      }
    }
    std::sort(row_cols.begin(), row_cols.end());
    for (int j : row_cols) {
      upper_cols.push_back(j);
      upper_vals.push_back(accumulator[j]);
    }
    upper_offsets[i + 1] = static_cast<int>(upper_cols.size());
  }
  // Mirror: row r = the entries (i, r), i < r, of the upper triangle, then its own upper row.
  std::vector<int> offsets(n + 1, 0);
  for (int i = 0; i < n; ++i) {
    offsets[i + 1] += upper_offsets[i + 1] - upper_offsets[i];
    for (int q = upper_offsets[i]; q < upper_offsets[i + 1]; ++q)
      if (upper_cols[q] != i) ++offsets[upper_cols[q] + 1];
  }
  for (int i = 0; i < n; ++i) offsets[i + 1] += offsets[i];
  std::vector<int> cols(offsets.back());
  std::vector<double> vals(offsets.back());
  std::vector<int> next(offsets.begin(), offsets.end() - 1);
  for (int i = 0; i < n; ++i)
    for (int q = upper_offsets[i]; q < upper_offsets[i + 1]; ++q) {
      const int j = upper_cols[q];
      if (j == i) continue;
      cols[next[j]] = i;
      vals[next[j]++] = upper_vals[q];
    }
  for (int i = 0; i < n; ++i)
    for (int q = upper_offsets[i]; q < upper_offsets[i + 1]; ++q) {
      cols[next[i]] = upper_cols[q];
      vals[next[i]++] = upper_vals[q];
    }

  NormalEquations result;
  result.ata = CsrMatrix::from_arrays(n, n, std::move(offsets), std::move(cols), std::move(vals));
  result.atb = Eigen::MatrixXd::Zero(n, b.cols());
  for (int c = 0; c < b.cols(); ++c) {
    for (int i = 0; i < n; ++i) {
      double sum = 0.0;
      for (int t = t_off[i]; t < t_off[i + 1]; ++t) {
        const int k = t_col[t];
        sum += t_val[t] * (weights ? weights[k] : 1.0) * b(k, c);
      }
      result.atb(i, c) = sum;
    }
  }
  return result;
}

}  // namespace

CsrMatrix CsrMatrix::from_triplets(int rows, int cols, const std::vector<Triplet>& triplets) {
  if (rows < 0 || cols < 0) {
    throw Error("sparse matrix: negative size " + std::to_string(rows) + "x" +
                std::to_string(cols));
  }
  const int count = static_cast<int>(triplets.size());
  for (int t = 0; t < count; ++t) {
    const Triplet& e = triplets[t];
    if (e.row < 0 || e.row >= rows || e.col < 0 || e.col >= cols) {
      throw Error("sparse matrix: triplet " + std::to_string(t) + " at (" +
                  std::to_string(e.row) + ", " + std::to_string(e.col) +
                  ") is outside the " + std::to_string(rows) + "x" + std::to_string(cols) +
                  " matrix");
    }
    if (!std::isfinite(e.value)) {
      throw Error("sparse matrix: triplet " + std::to_string(t) + " at (" +
                  std::to_string(e.row) + ", " + std::to_string(e.col) +
                  ") has a non-finite value");
    }
  }

  // Two stable counting sorts (by column, then by row) give row-major order with columns
  // increasing and duplicates kept in input order: O(nnz + rows + cols), no comparisons.
  std::vector<int> by_col(count);
  {
    std::vector<int> start(cols + 1, 0);
    for (const Triplet& e : triplets) ++start[e.col + 1];
    for (int c = 0; c < cols; ++c) start[c + 1] += start[c];
    for (int t = 0; t < count; ++t) by_col[start[triplets[t].col]++] = t;
  }
  std::vector<int> order(count);
  std::vector<int> row_start(rows + 1, 0);
  for (const Triplet& e : triplets) ++row_start[e.row + 1];
  for (int r = 0; r < rows; ++r) row_start[r + 1] += row_start[r];
  {
    std::vector<int> next(row_start.begin(), row_start.end() - 1);
    for (int t : by_col) order[next[triplets[t].row]++] = t;
  }

  CsrMatrix m;
  m.rows_ = rows;
  m.cols_ = cols;
  m.row_offsets_.assign(rows + 1, 0);
  m.col_indices_.reserve(count);
  m.values_.reserve(count);
  for (int r = 0; r < rows; ++r) {
    int last_col = -1;
    for (int k = row_start[r]; k < row_start[r + 1]; ++k) {
      const Triplet& e = triplets[order[k]];
      if (e.col == last_col) {
        m.values_.back() += e.value;
      } else {
        m.col_indices_.push_back(e.col);
        m.values_.push_back(e.value);
        last_col = e.col;
      }
    }
    m.row_offsets_[r + 1] = static_cast<int>(m.col_indices_.size());
  }
  m.col_indices_.shrink_to_fit();
  m.values_.shrink_to_fit();
  return m;
}

CsrMatrix CsrMatrix::from_arrays(int rows, int cols, std::vector<int> row_offsets,
                                 std::vector<int> col_indices, std::vector<double> values) {
  if (rows < 0 || cols < 0) {
    throw Error("sparse matrix: negative size " + std::to_string(rows) + "x" +
                std::to_string(cols));
  }
  if (static_cast<int>(row_offsets.size()) != rows + 1 || row_offsets.front() != 0 ||
      col_indices.size() != values.size() ||
      row_offsets.back() != static_cast<int>(col_indices.size())) {
    throw Error("sparse matrix: CSR arrays have inconsistent sizes");
  }
  for (int r = 0; r < rows; ++r) {
    if (row_offsets[r + 1] < row_offsets[r]) {
      throw Error("sparse matrix: row offsets decrease at row " + std::to_string(r));
    }
    for (int k = row_offsets[r]; k < row_offsets[r + 1]; ++k) {
      const int c = col_indices[k];
      if (c < 0 || c >= cols || (k > row_offsets[r] && c <= col_indices[k - 1])) {
        throw Error("sparse matrix: row " + std::to_string(r) +
                    " has a column index out of range or out of order");
      }
    }
  }
  CsrMatrix m;
  m.rows_ = rows;
  m.cols_ = cols;
  m.row_offsets_ = std::move(row_offsets);
  m.col_indices_ = std::move(col_indices);
  m.values_ = std::move(values);
  return m;
}

CsrMatrix CsrMatrix::from_eigen(const Eigen::SparseMatrix<double, Eigen::RowMajor>& a) {
  CsrMatrix m;
  m.rows_ = static_cast<int>(a.rows());
  m.cols_ = static_cast<int>(a.cols());
  m.row_offsets_.assign(m.rows_ + 1, 0);
  m.col_indices_.reserve(a.nonZeros());
  m.values_.reserve(a.nonZeros());
  for (int r = 0; r < m.rows_; ++r) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(a, r); it; ++it) {
      m.col_indices_.push_back(static_cast<int>(it.col()));
      m.values_.push_back(it.value());
    }
    m.row_offsets_[r + 1] = static_cast<int>(m.col_indices_.size());
  }
  return m;
}

double CsrMatrix::coeff(int row, int col) const {
  assert(row >= 0 && row < rows_ && col >= 0 && col < cols_);
  const auto begin = col_indices_.begin() + row_offsets_[row];
  const auto end = col_indices_.begin() + row_offsets_[row + 1];
  const auto it = std::lower_bound(begin, end, col);
  return (it != end && *it == col) ? values_[it - col_indices_.begin()] : 0.0;
}

void CsrMatrix::multiply(const Eigen::Ref<const Eigen::VectorXd>& x,
                         Eigen::Ref<Eigen::VectorXd> y) const {
  assert(x.size() == cols_ && y.size() == rows_);
  spmv(*this, 1.0, x.data(), 0.0, y.data());
}

void CsrMatrix::multiply_add(double alpha, const Eigen::Ref<const Eigen::VectorXd>& x,
                             Eigen::Ref<Eigen::VectorXd> y) const {
  assert(x.size() == cols_ && y.size() == rows_);
  spmv(*this, alpha, x.data(), 1.0, y.data());
}

Eigen::VectorXd CsrMatrix::operator*(const Eigen::VectorXd& x) const {
  Eigen::VectorXd y(rows_);
  multiply(x, y);
  return y;
}

Eigen::VectorXd CsrMatrix::diagonal() const {
  const int n = std::min(rows_, cols_);
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i) d[i] = coeff(i, i);
  return d;
}

CsrMatrix CsrMatrix::transpose() const {
  CsrMatrix t;
  t.rows_ = cols_;
  t.cols_ = rows_;
  t.row_offsets_.assign(cols_ + 1, 0);
  for (int c : col_indices_) ++t.row_offsets_[c + 1];
  for (int c = 0; c < cols_; ++c) t.row_offsets_[c + 1] += t.row_offsets_[c];
  t.col_indices_.resize(col_indices_.size());
  t.values_.resize(values_.size());
  std::vector<int> next(t.row_offsets_.begin(), t.row_offsets_.end() - 1);
  // Scanning rows in increasing order keeps the transposed rows sorted by column.
  for (int r = 0; r < rows_; ++r) {
    for (int k = row_offsets_[r]; k < row_offsets_[r + 1]; ++k) {
      const int dst = next[col_indices_[k]]++;
      t.col_indices_[dst] = r;
      t.values_[dst] = values_[k];
    }
  }
  return t;
}

Eigen::SparseMatrix<double, Eigen::RowMajor> CsrMatrix::to_eigen() const {
  Eigen::SparseMatrix<double, Eigen::RowMajor> a(rows_, cols_);
  a.resizeNonZeros(nnz());
  std::copy(row_offsets_.begin(), row_offsets_.end(), a.outerIndexPtr());
  std::copy(col_indices_.begin(), col_indices_.end(), a.innerIndexPtr());
  std::copy(values_.begin(), values_.end(), a.valuePtr());
  return a;
}

Eigen::MatrixXd CsrMatrix::to_dense() const {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(rows_, cols_);
  for (int r = 0; r < rows_; ++r) {
    for (int k = row_offsets_[r]; k < row_offsets_[r + 1]; ++k) {
      d(r, col_indices_[k]) += values_[k];
    }
  }
  return d;
}

CsrMatrix transpose_times_self(const CsrMatrix& a) {
  return normal_equations_impl(a, Eigen::MatrixXd::Zero(a.rows(), 0), nullptr).ata;
}

NormalEquations normal_equations(const CsrMatrix& a, const Eigen::MatrixXd& b) {
  return normal_equations_impl(a, b, nullptr);
}

NormalEquations normal_equations(const CsrMatrix& a, const Eigen::MatrixXd& b,
                                 const Eigen::VectorXd& weights) {
  assert(weights.size() == a.rows());
  return normal_equations_impl(a, b, weights.data());
}

}  // namespace volspline::linalg
