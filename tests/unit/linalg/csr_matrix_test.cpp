// SPDX-License-Identifier: MIT
#include "core/linalg/csr_matrix.h"

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "tests/unit/linalg/test_systems.h"

namespace linalg = volspline::linalg;
using linalg::CsrMatrix;
using linalg::Triplet;

namespace {

// A 7×5 matrix with empty rows 0 and 4, some rows denser; values from a fixed seed.
CsrMatrix sample_rectangular() {
  std::vector<Triplet> t;
  const Eigen::VectorXd r = linalg::testing::pseudo_random_vector(40, 3);
  int k = 0;
  for (int row : {1, 2, 3, 5, 6}) {
    for (int col = 0; col < 5; ++col) {
      if ((row + 2 * col) % 3 != 0) t.push_back({row, col, r[k++]});
    }
  }
  return CsrMatrix::from_triplets(7, 5, t);
}

std::string error_message(const std::vector<Triplet>& t, int rows, int cols) {
  try {
    CsrMatrix::from_triplets(rows, cols, t);
  } catch (const volspline::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("from_triplets sums duplicates, sorts columns and keeps empty rows") {
  const std::vector<Triplet> t = {{2, 3, 1.0}, {0, 1, 2.0}, {2, 0, 4.0}, {2, 3, 0.5},
                                  {0, 1, -2.0}, {3, 2, 7.0}};
  const CsrMatrix a = CsrMatrix::from_triplets(4, 4, t);
  CHECK(a.rows() == 4);
  CHECK(a.cols() == 4);
  CHECK(a.nnz() == 4);  // (0,1) sums to an explicit zero, which is kept
  CHECK(a.row_offsets() == std::vector<int>{0, 1, 1, 3, 4});
  CHECK(a.col_indices() == std::vector<int>{1, 0, 3, 2});
  CHECK(a.values() == std::vector<double>{0.0, 4.0, 1.5, 7.0});
  CHECK(a.coeff(2, 3) == 1.5);
  CHECK(a.coeff(1, 1) == 0.0);
}

TEST_CASE("from_triplets is independent of the order of distinct entries") {
  const std::vector<Triplet> t1 = {{0, 0, 1.0}, {1, 2, 2.0}, {0, 2, 3.0}, {1, 0, 4.0}};
  const std::vector<Triplet> t2 = {{1, 0, 4.0}, {0, 2, 3.0}, {1, 2, 2.0}, {0, 0, 1.0}};
  const CsrMatrix a = CsrMatrix::from_triplets(2, 3, t1);
  const CsrMatrix b = CsrMatrix::from_triplets(2, 3, t2);
  CHECK(a.row_offsets() == b.row_offsets());
  CHECK(a.col_indices() == b.col_indices());
  CHECK(a.values() == b.values());
}

TEST_CASE("from_triplets rejects bad entries with the triplet index in the message") {
  CHECK(error_message({{0, 0, 1.0}, {1, 1, 1.0}, {2, 0, 1.0}}, 2, 2).find("triplet 2") !=
        std::string::npos);
  CHECK(error_message({{0, -1, 1.0}}, 2, 2).find("outside the 2x2 matrix") != std::string::npos);
  CHECK(error_message({{0, 0, std::nan("")}}, 2, 2).find("non-finite") != std::string::npos);
  CHECK(error_message({}, -1, 2).find("negative size") != std::string::npos);
}

TEST_CASE("from_arrays validates the CSR structure") {
  CHECK_NOTHROW(CsrMatrix::from_arrays(2, 2, {0, 1, 2}, {1, 0}, {1.0, 2.0}));
  CHECK_THROWS_WITH_AS(CsrMatrix::from_arrays(2, 2, {0, 1}, {1}, {1.0}),
                       "sparse matrix: CSR arrays have inconsistent sizes", volspline::Error);
  CHECK_THROWS_WITH_AS(CsrMatrix::from_arrays(1, 3, {0, 2}, {2, 1}, {1.0, 2.0}),
                       "sparse matrix: row 0 has a column index out of range or out of order",
                       volspline::Error);
  CHECK_THROWS_WITH_AS(CsrMatrix::from_arrays(2, 2, {0, 2, 1}, {0, 1}, {1.0, 2.0}),
                       doctest::Contains("inconsistent"), volspline::Error);
}

TEST_CASE("empty matrices") {
  const CsrMatrix a;
  CHECK(a.rows() == 0);
  CHECK(a.nnz() == 0);
  const CsrMatrix b = CsrMatrix::from_triplets(3, 2, {});
  CHECK(b.nnz() == 0);
  CHECK((b * Eigen::VectorXd::Ones(2)).isZero(0.0));
  CHECK(b.transpose().rows() == 2);
}

TEST_CASE("SpMV, multiply_add, diagonal and transpose agree with dense") {
  const CsrMatrix a = sample_rectangular();
  const Eigen::MatrixXd d = a.to_dense();
  const Eigen::VectorXd x = linalg::testing::pseudo_random_vector(5, 11);
  // Tolerance: a 5-term dot product of values in [-1,1] rounds to well under 1e-14.
  CHECK((a * x - d * x).norm() <= 1e-14);
  Eigen::VectorXd y = linalg::testing::pseudo_random_vector(7, 12);
  const Eigen::VectorXd expected = y + 0.75 * d * x;
  a.multiply_add(0.75, x, y);
  CHECK((y - expected).norm() <= 1e-14);

  CHECK(a.diagonal() == d.diagonal().head(5));
  const CsrMatrix at = a.transpose();
  CHECK(at.to_dense() == d.transpose());
  const CsrMatrix att = at.transpose();
  CHECK(att.row_offsets() == a.row_offsets());
  CHECK(att.col_indices() == a.col_indices());
  CHECK(att.values() == a.values());
}

TEST_CASE("Eigen conversion round-trips the pattern") {
  const CsrMatrix a = sample_rectangular();
  const Eigen::SparseMatrix<double, Eigen::RowMajor> e = a.to_eigen();
  CHECK(e.nonZeros() == a.nnz());
  CHECK(Eigen::MatrixXd(e) == a.to_dense());
  const CsrMatrix b = CsrMatrix::from_eigen(e);
  CHECK(b.row_offsets() == a.row_offsets());
  CHECK(b.col_indices() == a.col_indices());
  CHECK(b.values() == a.values());
}

TEST_CASE("normal equations match dense AᵀA and AᵀB") {
  const CsrMatrix a = sample_rectangular();
  const Eigen::MatrixXd d = a.to_dense();
  Eigen::MatrixXd b(7, 3);
  for (int c = 0; c < 3; ++c) b.col(c) = linalg::testing::pseudo_random_vector(7, 20 + c);
  // Tolerance: sums of at most 7 products of values in [-1,1].
  const linalg::NormalEquations ne = linalg::normal_equations(a, b);
  CHECK((ne.ata.to_dense() - d.transpose() * d).norm() <= 1e-13);
  CHECK((ne.atb - d.transpose() * b).norm() <= 1e-13);
  CHECK(ne.ata.to_dense() == ne.ata.to_dense().transpose());  // summation order is symmetric
  CHECK((linalg::transpose_times_self(a).to_dense() - d.transpose() * d).norm() <= 1e-13);

  const Eigen::VectorXd w = linalg::testing::pseudo_random_vector(7, 30).cwiseAbs();
  const linalg::NormalEquations nw = linalg::normal_equations(a, b, w);
  CHECK((nw.ata.to_dense() - d.transpose() * w.asDiagonal() * d).norm() <= 1e-13);
  CHECK((nw.atb - d.transpose() * w.asDiagonal() * b).norm() <= 1e-13);
}
