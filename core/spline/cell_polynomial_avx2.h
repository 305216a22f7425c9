// SPDX-License-Identifier: MIT
// Internal: a TSpline cell's tricubic power form evaluated with AVX2 (cell_polynomial_avx2.cpp),
// one 4-lane register per monomial: lanes 0 .. D−1 the numerator's components, lane D the
// denominator. No includes: that file is compiled with -mavx2, and nothing inline may come from
// a header there.
#pragma once

namespace volspline::spline::detail {

#if defined(VOLSPLINE_AVX2_KERNELS)
/// The nested Horner of a tricubic power form at s (3 doubles in [0, 1]): numerator holds monomial
/// m = (4a + b)·4 + c of s0^a s1^b s2^c at [m·D .. m·D + D), denominator (null: none; only for
/// D < 4) at [m]. Writes lanes[0 .. D) for the numerator and lanes[D] for the denominator.
/// Reads up to 4 − D doubles past the numerator's last monomial (the caller pads the array).
/// The products and sums of TSpline's portable Horner, in the same order and without FMA, so
/// both give the same bits. D in 1..4.
template <int D, bool kDenominator>
void cell_horner_avx2(const double* numerator, const double* denominator, const double* s, double* lanes);
/// As cell_horner_avx2, plus the derivatives with respect to s0, s1, s2: lanes[4·k + l] for
/// k = 0 (value), 1 + axis (∂/∂s_axis), l the lane as above. The bits of the portable gradient.
template <int D, bool kDenominator>
void cell_horner_gradient_avx2(const double* numerator, const double* denominator, const double* s, double* lanes);
/// The nested Horner of a K-channel tricubic power form (channel d of monomial m at
/// coef[m·K + d]) at four points of one cell, one point per lane: s[4·axis + p] is point p's local
/// coordinate along axis. Writes out[4·d + p]. Each lane runs horner3's products and sums in
/// their order without FMA: the bits of the portable Horner at that point. K in 1..4.
template <int K>
void cell_horner_points_avx2(const double* coef, const double* s, double* out);
/// As cell_horner_points_avx2, plus the derivatives: out[4·(K·k + d) + p] for k = 0 (value),
/// 1 + axis (∂/∂s_axis). The bits of the portable gradient at each point.
template <int K>
void cell_horner_gradient_points_avx2(const double* coef, const double* s, double* out);
#endif

}  // namespace volspline::spline::detail
