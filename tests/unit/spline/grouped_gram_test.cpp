// SPDX-License-Identifier: MIT
#include "core/spline/grouped_gram.h"

#include <random>

#include <doctest/doctest.h>

using namespace volspline;

TEST_CASE("the grouped Gram assembly equals the dense normal equations, both triangles") {
  // Three overlapping groups over 6 columns, rows added in two batches for group 0.
  const int n = 6;
  const std::vector<int> offsets = {0, 3, 5, 8};
  const std::vector<int> cols = {0, 2, 3, 1, 2, 3, 4, 5};
  spline::GroupedGram gram(n, 2, offsets, cols);
  CHECK(gram.num_groups() == 3);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd dense_m = Eigen::MatrixXd::Zero(0, n), dense_t(0, 2);
  auto add = [&](int g, int rows) {
    const int k = gram.group_size(g);
    Eigen::MatrixXd block(rows, k), t(rows, 2);
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < k; ++c) block(r, c) = u(rng);
      t.row(r) << u(rng), u(rng);
    }
    gram.add(g, block, t);
    const Eigen::Index base = dense_m.rows();
    dense_m.conservativeResize(base + rows, n);
    dense_t.conservativeResize(base + rows, 2);
    dense_m.bottomRows(rows).setZero();
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < k; ++c) dense_m(base + r, gram.group_columns(g)[c]) = block(r, c);
      dense_t.row(base + r) = t.row(r);
    }
  };
  add(0, 4);
  add(1, 2);
  add(2, 5);
  add(0, 1);
  const Eigen::MatrixXd expected = dense_m.transpose() * dense_m;
  // Tolerance: sums of a few products of numbers in [-1, 1], summed in another order.
  CHECK((gram.rhs() - dense_m.transpose() * dense_t).cwiseAbs().maxCoeff() < 1e-12);
  const linalg::CsrMatrix a = gram.take_symmetric();
  Eigen::MatrixXd got = Eigen::MatrixXd::Zero(n, n);
  for (int r = 0; r < n; ++r) {
    int previous = -1;
    for (int p = a.row_offsets()[r]; p < a.row_offsets()[r + 1]; ++p) {
      CHECK(a.col_indices()[p] > previous);  // sorted rows
      previous = a.col_indices()[p];
      got(r, a.col_indices()[p]) = a.values()[p];
    }
  }
  CHECK((got - expected).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((got - got.transpose()).cwiseAbs().maxCoeff() == 0.0);  // mirrored, exactly symmetric
  // Columns 0 and 1 share no group: no stored entry; the diagonal is always stored.
  for (int p = a.row_offsets()[0]; p < a.row_offsets()[1]; ++p) CHECK(a.col_indices()[p] != 1);
  CHECK(a.nnz() == 6 + 2 * (3 + 1 + 3));  // diagonal + strict upper {02,03,23}, {12}, {34,35,45}
}

TEST_CASE("the upper triangle keeps the diagonal first in every row") {
  spline::GroupedGram gram(3, 1, {0, 3}, {0, 1, 2});
  gram.add(0, (Eigen::MatrixXd(1, 3) << 1.0, 2.0, 3.0).finished(), (Eigen::MatrixXd(1, 1) << 1.0).finished());
  const linalg::CsrMatrix a = gram.take_upper();
  CHECK(a.nnz() == 6);
  CHECK(a.row_offsets() == std::vector<int>{0, 3, 5, 6});
  CHECK(a.col_indices() == std::vector<int>{0, 1, 2, 1, 2, 2});
  CHECK(a.values() == std::vector<double>{1.0, 2.0, 3.0, 4.0, 6.0, 9.0});
}

TEST_CASE("an unused column keeps its diagonal with zero value") {
  spline::GroupedGram gram(3, 1, {0, 2}, {0, 2});
  gram.add(0, (Eigen::MatrixXd(1, 2) << 1.0, 2.0).finished(), (Eigen::MatrixXd(1, 1) << 3.0).finished());
  const linalg::CsrMatrix a = gram.take_symmetric();
  CHECK(a.nnz() == 5);
  CHECK(a.row_offsets()[2] - a.row_offsets()[1] == 1);
  CHECK(a.values()[a.row_offsets()[1]] == 0.0);
  CHECK(gram.rhs()(2, 0) == 6.0);
}
