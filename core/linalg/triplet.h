// SPDX-License-Identifier: MIT
#pragma once

namespace volspline::linalg {

/// One entry of a sparse matrix given as a list of triplets; duplicates are summed by whoever
/// assembles the matrix (CsrMatrix::from_triplets).
struct Triplet {
  int row = 0;
  int col = 0;
  double value = 0.0;
};

}  // namespace volspline::linalg
