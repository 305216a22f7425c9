// SPDX-License-Identifier: MIT
#pragma once

#include "core/spline/bspline_basis.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Result of inserting one knot into a local knot vector R: N_R = c1 N_R1 + c2 N_R2 (Eq. 4.8).
struct KnotInsertion {
  LocalKnots first{};               ///< R1 (Table 4.1), the left child.
  LocalKnots second{};              ///< R2 (Table 4.1), the right child.
  double first_coefficient = 0.0;   ///< c1 = min((k − r0)/(r3 − r0), 1), in [0, 1].
  double second_coefficient = 0.0;  ///< c2 = min((r4 − k)/(r4 − r1), 1), in [0, 1].
};

/// Inserts knot k into R = [r0..r4] (Table 4.1, Eq. 4.8). Zero denominators follow x/0 = ∞ for
/// x > 0 and 0/0 = 0 before the min, i.e. c1 = 1 if k >= r3 and c2 = 1 if k <= r1. A child whose
/// knots are all equal is the zero function (its coefficient is then irrelevant). k = r0 or
/// k = r4 is allowed and gives a zero coefficient or an unchanged child. Throws volspline::Error
/// if k is not finite or outside [r0, r4].
KnotInsertion insert_knot(const LocalKnots& r, double k);

/// Result of splitting a blending function along one axis: B = c1 B1 + c2 B2 (Eq. 4.9).
struct BlendingSplit {
  BlendingKnots first{};            ///< knots of B1: R1 on the split axis, unchanged elsewhere.
  BlendingKnots second{};           ///< knots of B2: R2 on the split axis, unchanged elsewhere.
  double first_coefficient = 0.0;   ///< c1 of insert_knot.
  double second_coefficient = 0.0;  ///< c2 of insert_knot.
};

/// Splits blending function `knots` by inserting knot k along axis (0 = u, 1 = v, 2 = w); the
/// weighted function w B becomes (w c1) B1 + (w c2) B2 (Eq. 4.9). Throws like insert_knot.
BlendingSplit split_blending_function(const BlendingKnots& knots, int axis, double k);

}  // namespace volspline::spline
