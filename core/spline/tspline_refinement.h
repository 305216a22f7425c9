// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "core/spline/tspline.h"

namespace volspline::spline {

/// Knots to insert into one blending function, per axis (u, v, w), any order.
using NewKnots = std::array<std::vector<double>, 3>;

/// Re-expresses every blending function of `spline` after inserting new_knots[i] into function i
/// (§4.3.3 steps 2–3, Eq. 4.9), leaving F and Σ w_i B_i unchanged.
///
/// Along each axis, a knot strictly inside (r0, r4) of a function is inserted into it and then
/// into each of its children whose support still contains it strictly (so the function becomes
/// the windows of its refined knot vector); knots at or outside the ends are ignored, a knot equal
/// to an existing interior knot raises its multiplicity. Afterwards functions with identical
/// knot vectors are merged: weight W = Σ w c, control point P = Σ (w c p) / Σ (w c), so
/// W P B = Σ w c p B exactly. Output order: first appearance while visiting the input functions
/// in order (an untouched function keeps its relative order), so the result is deterministic.
/// new_knots has num_functions() entries. Throws volspline::Error naming the function if the
/// size differs or a knot is not finite.
TSpline refine_blending_functions(const TSpline& spline, const std::vector<NewKnots>& new_knots);

/// §4.3.3 step 3 loop: asks required_knots for every blending function of the current spline
/// (the knots its T-mesh ray-tracing vector R* has and R lacks), refines with
/// refine_blending_functions, and repeats until no function needs a knot. Throws
/// volspline::Error if that does not happen within max_rounds rounds.
TSpline refine_until_no_new_knot(const TSpline& spline,
                                 const std::function<NewKnots(const BlendingKnots&)>& required_knots,
                                 int max_rounds = 64);

}  // namespace volspline::spline
