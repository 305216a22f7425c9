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
  std::vector<int> kept_offsets(1, 0), kept_cols;
  std::vector<double> kept_values;
  for (int i = 0; i < n; ++i) {
    for (int k = offsets[i]; k < offsets[i + 1]; ++k) {
      const int j = cols[k];
      if (j == i || std::abs(values[k]) >= drop_ * std::sqrt(diagonal[i] * diagonal[j])) {
        kept_cols.push_back(j);
        kept_values.push_back(values[k]);
      }
    }
    kept_offsets.push_back(static_cast<int>(kept_cols.size()));
  }
  ic_.compute(linalg::CsrMatrix::from_arrays(n, a.cols(), std::move(kept_offsets), std::move(kept_cols),
                                             std::move(kept_values)));
}

}  // namespace volspline::spline
