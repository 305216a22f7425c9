// SPDX-License-Identifier: MIT
#include "core/spline/knot_insertion.h"

#include <cassert>
#include <cmath>
#include <string>

#include "core/common/error.h"

namespace volspline::spline {

KnotInsertion insert_knot(const LocalKnots& r, double k) {
  if (!(std::isfinite(k) && k >= r[0] && k <= r[4])) {
    throw Error("knot insertion: knot " + std::to_string(k) + " is outside the knot vector [" +
                std::to_string(r[0]) + ", " + std::to_string(r[4]) + "]");
  }
  // Table 4.1: k goes after the last knot <= k among r1..r3 (the last row is closed at r4).
  const int slot = int(k >= r[1]) + int(k >= r[2]) + int(k >= r[3]);
  KnotInsertion out;
  // Full refined vector [r0, .., k, .., r4] has 6 knots; R1 is its first 5, R2 its last 5.
  double refined[6];
  for (int i = 0; i < 6; ++i) {
    if (i <= slot) refined[i] = r[i];
    else if (i == slot + 1) refined[i] = k;
    else refined[i] = r[i - 1];
  }
  for (int i = 0; i < 5; ++i) {
    out.first[i] = refined[i];
    out.second[i] = refined[i + 1];
  }
  // Eq. 4.8 with the min(·, 1) written as a branch, which also avoids 0/0.
  out.first_coefficient = k >= r[3] ? 1.0 : (k - r[0]) / (r[3] - r[0]);
  out.second_coefficient = k <= r[1] ? 1.0 : (r[4] - k) / (r[4] - r[1]);
  return out;
}

BlendingSplit split_blending_function(const BlendingKnots& knots, int axis, double k) {
  assert(axis >= 0 && axis < 3);
  const KnotInsertion ins = insert_knot(knots[axis], k);
  BlendingSplit out;
  out.first = knots;
  out.second = knots;
  out.first[axis] = ins.first;
  out.second[axis] = ins.second;
  out.first_coefficient = ins.first_coefficient;
  out.second_coefficient = ins.second_coefficient;
  return out;
}

}  // namespace volspline::spline
