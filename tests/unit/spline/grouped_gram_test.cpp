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

TEST_CASE("add_all equals the dense normal equations and gives the same bits for every thread count") {
  // 600 columns in 900 overlapping groups of 40 sorted columns, 1 to 6 rows each and 60 rows in
  // every 50th (those store their Gram block): several batches and row ranges.
  const int n = 600, groups = 900;
  std::vector<int> offsets(1, 0), cols;
  std::mt19937_64 rng(11);
  for (int g = 0; g < groups; ++g) {
    const int start = static_cast<int>(rng() % (n - 80));
    for (int c = 0; c < 40; ++c) cols.push_back(start + 2 * c);
    offsets.push_back(static_cast<int>(cols.size()));
  }
  std::vector<int> row_counts(groups);
  for (int g = 0; g < groups; ++g) row_counts[g] = g % 50 == 7 ? 60 : 1 + g % 6;
  auto rows = [&](int g, Eigen::MatrixXd& block, Eigen::MatrixXd& t) {
    std::mt19937_64 local(1000 + g);  // the rows of a group depend only on g
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int r = row_counts[g];
    block.resize(r, 40);
    t.resize(r, 3);
    for (int i = 0; i < r; ++i) {
      for (int c = 0; c < 40; ++c) block(i, c) = u(local);
      for (int c = 0; c < 3; ++c) t(i, c) = u(local);
    }
  };
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(n, n), expected_rhs = Eigen::MatrixXd::Zero(n, 3);
  std::vector<char> coupled(static_cast<std::size_t>(n) * n, 0);
  for (int g = 0; g < groups; ++g) {
    Eigen::MatrixXd block, t;
    rows(g, block, t);
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(block.rows(), n);
    for (int c = 0; c < 40; ++c) m.col(cols[offsets[g] + c]) = block.col(c);
    expected += m.transpose() * m;
    expected_rhs += m.transpose() * t;
    for (int a = 0; a < 40; ++a)
      for (int b = 0; b < 40; ++b) coupled[static_cast<std::size_t>(cols[offsets[g] + a]) * n + cols[offsets[g] + b]] = 1;
  }
  linalg::CsrMatrix first;
  Eigen::MatrixXd first_rhs;
  for (int threads : {1, 2, 3}) {
    CAPTURE(threads);
    spline::GroupedGram gram(n, 3, offsets, cols, threads);
    gram.add_all(row_counts, rows);
    const linalg::CsrMatrix got = gram.take_upper();
    if (threads == 1) {
      // Tolerance: sums of up to ~100 products of numbers in [-1, 1], in another order.
      CHECK((gram.rhs() - expected_rhs).cwiseAbs().maxCoeff() < 1e-11);
      double worst = 0.0;
      long stored = 0;
      for (int i = 0; i < n; ++i) {
        CHECK(got.col_indices()[got.row_offsets()[i]] == i);  // the diagonal first
        for (int p = got.row_offsets()[i]; p < got.row_offsets()[i + 1]; ++p) {
          const int j = got.col_indices()[p];
          if (p > got.row_offsets()[i]) CHECK(j > (p == got.row_offsets()[i] + 1 ? i : got.col_indices()[p - 1]));
          worst = std::max(worst, std::abs(got.values()[p] - expected(i, j)));
        }
        for (int j = i + 1; j < n; ++j) stored += coupled[static_cast<std::size_t>(i) * n + j];
      }
      CHECK(worst < 1e-11);
      CHECK(got.nnz() == stored + n);  // the union of the group blocks plus the diagonal
      first = got;
      first_rhs = gram.rhs();
    } else {
      CHECK(gram.rhs() == first_rhs);
      CHECK(got.row_offsets() == first.row_offsets());
      CHECK(got.col_indices() == first.col_indices());
      CHECK(got.values() == first.values());  // exact: every entry summed in the same order
    }
  }
}
