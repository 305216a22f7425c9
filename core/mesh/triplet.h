// SPDX-License-Identifier: MIT
#pragma once

#include "core/linalg/triplet.h"

namespace volspline::mesh {

/// Mesh operators are assembled as linalg triplets so they go straight into linalg::CsrMatrix.
using Triplet = linalg::Triplet;

}  // namespace volspline::mesh
