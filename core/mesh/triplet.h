// SPDX-License-Identifier: MIT
#pragma once

namespace volspline::mesh {

/// One entry of a sparse matrix given as a list of triplets; duplicates are meant to be summed
/// by whoever assembles the matrix (e.g. linalg::CsrMatrix).
struct Triplet {
  int row = 0;
  int col = 0;
  double value = 0.0;
};

}  // namespace volspline::mesh
