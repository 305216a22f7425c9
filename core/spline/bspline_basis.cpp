// SPDX-License-Identifier: MIT
#include "core/spline/bspline_basis.h"

#include <cmath>

namespace volspline::spline {

bool local_knots_valid(const LocalKnots& r) {
  for (int i = 0; i < 5; ++i) {
    if (!std::isfinite(r[i])) return false;
    if (i > 0 && r[i] < r[i - 1]) return false;
  }
  return r[0] < r[4];
}

}  // namespace volspline::spline
