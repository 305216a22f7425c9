// SPDX-License-Identifier: MIT
#include "core/spline/sparsified_cholesky.h"

#include <cmath>
#include <vector>

namespace volspline::spline {

void SparsifiedCholesky::compute(const linalg::CsrMatrix& a) {
  const int n = a.rows();
  const auto& offsets = a.row_offsets();
  const auto& cols = a.col_indices();
  const auto& values = a.values();
  std::vector<double> diagonal(n, 0.0);
  for (int i = 0; i < n; ++i)
    for (int k = offsets[i]; k < offsets[i + 1]; ++k)
      if (cols[k] == i) diagonal[i] = std::abs(values[k]);
  auto kept = [&](int i, int k) {
    const int j = cols[k];
    return j == i || (j > i && std::abs(values[k]) >= drop_ * std::sqrt(diagonal[i] * diagonal[j]));
  };
  // The kept upper entries (i, j ≥ i) transposed into the lower triangle IC(0) reads; rows are
  // filled in increasing i, so every row's columns come out sorted with the diagonal last.
  std::vector<int> lower_offsets(n + 1, 0);
  for (int i = 0; i < n; ++i)
    for (int k = offsets[i]; k < offsets[i + 1]; ++k)
      if (kept(i, k)) ++lower_offsets[cols[k] + 1];
  for (int i = 0; i < n; ++i) lower_offsets[i + 1] += lower_offsets[i];
  std::vector<int> lower_cols(lower_offsets[n]);
  std::vector<double> lower_values(lower_offsets[n]);
  std::vector<int> fill(lower_offsets.begin(), lower_offsets.end() - 1);
  for (int i = 0; i < n; ++i)
    for (int k = offsets[i]; k < offsets[i + 1]; ++k)
      if (kept(i, k)) {
        const int p = fill[cols[k]]++;
        lower_cols[p] = i;
        lower_values[p] = values[k];
      }
  ic_.compute(linalg::CsrMatrix::from_arrays(n, a.cols(), std::move(lower_offsets), std::move(lower_cols),
                                             std::move(lower_values)));
}

}  // namespace volspline::spline
