// SPDX-License-Identifier: MIT
#pragma once

#include <array>

namespace volspline::spline {

/// Local knot vector [r0, r1, r2, r3, r4] of one cubic B-spline basis function N_R
/// (thesis §4.2.2: the ray-tracing knot vector of a blending function). Non-decreasing; knots
/// may repeat (up to all five, which gives the zero function).
using LocalKnots = std::array<double, 5>;

/// Whether the support of a basis function includes its last knot r4.
///
/// Basis functions are right-continuous pieces on half-open knot intervals [r_j, r_{j+1}), so the
/// natural support is [r0, r4). A function whose support ends at the end of the whole domain must
/// still be evaluated at that end (otherwise partition of unity fails at t = domain end): such a
/// function is evaluated with `Closed`, which takes the left limit at t = r4, i.e. the domain is
/// closed at its last knot.
enum class RightEnd {
  Open,    ///< support [r0, r4); N(r4) = 0. For every function that does not end at the domain end.
  Closed,  ///< support [r0, r4]; N(r4) = left limit. For functions with r4 = end of the domain.
};

/// Value and derivatives d/dt, d²/dt², d³/dt³ of one cubic basis function at one parameter.
struct BasisDerivatives {
  double value = 0.0;
  double d1 = 0.0;
  double d2 = 0.0;
  double d3 = 0.0;
};

namespace detail {

// The parameter axes' names in messages.
inline constexpr const char* kAxisName[3] = {"u", "v", "w"};

// Cox-de Boor with the 0/0 := 0 convention: a zero-length knot span contributes nothing.
inline double inverse_or_zero(double length) { return length > 0.0 ? 1.0 / length : 0.0; }

}  // namespace detail

/// Index j in 0..3 of the non-empty knot interval [r_j, r_{j+1}) that contains t, or -1 if t is
/// outside the support ([r0, r4) for RightEnd::Open, [r0, r4] for RightEnd::Closed; NaN is
/// outside). With RightEnd::Closed and t = r4 > r0 this is the last non-empty interval.
inline int cubic_basis_interval(const LocalKnots& r, double t, RightEnd end) {
  if (!(t >= r[0])) return -1;
  if (t < r[4]) return int(t >= r[1]) + int(t >= r[2]) + int(t >= r[3]);
  if (t == r[4] && end == RightEnd::Closed && r[0] < r[4]) {
    int j = 3;
    while (r[j] == r[4]) --j;
    return j;
  }
  return -1;
}

/// Value of the polynomial piece of N_R on knot interval j (0..3) at t (any t: the piece is
/// extended as a polynomial). Precondition: r[j] < r[j+1].
inline double cubic_basis_piece_value(const LocalKnots& r, int j, double t) {
  using detail::inverse_or_zero;
  double n0[4] = {0.0, 0.0, 0.0, 0.0};
  n0[j] = 1.0;
  double n1[3];
  for (int i = 0; i < 3; ++i) {
    n1[i] = (t - r[i]) * inverse_or_zero(r[i + 1] - r[i]) * n0[i] +
            (r[i + 2] - t) * inverse_or_zero(r[i + 2] - r[i + 1]) * n0[i + 1];
  }
  double n2[2];
  for (int i = 0; i < 2; ++i) {
    n2[i] = (t - r[i]) * inverse_or_zero(r[i + 2] - r[i]) * n1[i] +
            (r[i + 3] - t) * inverse_or_zero(r[i + 3] - r[i + 1]) * n1[i + 1];
  }
  return (t - r[0]) * inverse_or_zero(r[3] - r[0]) * n2[0] +
         (r[4] - t) * inverse_or_zero(r[4] - r[1]) * n2[1];
}

/// Value and derivatives up to third order of the polynomial piece of N_R on knot interval j
/// (0..3) at t. Precondition: r[j] < r[j+1].
inline BasisDerivatives cubic_basis_piece_derivatives(const LocalKnots& r, int j, double t) {
  using detail::inverse_or_zero;
  double n0[4] = {0.0, 0.0, 0.0, 0.0};
  n0[j] = 1.0;
  double inv1[4], inv2[3], inv3[2];
  for (int i = 0; i < 4; ++i) inv1[i] = inverse_or_zero(r[i + 1] - r[i]);
  for (int i = 0; i < 3; ++i) inv2[i] = inverse_or_zero(r[i + 2] - r[i]);
  for (int i = 0; i < 2; ++i) inv3[i] = inverse_or_zero(r[i + 3] - r[i]);
  double n1[3], dn1[3];
  for (int i = 0; i < 3; ++i) {
    n1[i] = (t - r[i]) * inv1[i] * n0[i] + (r[i + 2] - t) * inv1[i + 1] * n0[i + 1];
    dn1[i] = inv1[i] * n0[i] - inv1[i + 1] * n0[i + 1];
  }
  double n2[2], dn2[2], ddn2[2];
  for (int i = 0; i < 2; ++i) {
    n2[i] = (t - r[i]) * inv2[i] * n1[i] + (r[i + 3] - t) * inv2[i + 1] * n1[i + 1];
    dn2[i] = 2.0 * (inv2[i] * n1[i] - inv2[i + 1] * n1[i + 1]);
    ddn2[i] = 2.0 * (inv2[i] * dn1[i] - inv2[i + 1] * dn1[i + 1]);
  }
  BasisDerivatives out;
  out.value = (t - r[0]) * inv3[0] * n2[0] + (r[4] - t) * inv3[1] * n2[1];
  out.d1 = 3.0 * (inv3[0] * n2[0] - inv3[1] * n2[1]);
  out.d2 = 3.0 * (inv3[0] * dn2[0] - inv3[1] * dn2[1]);
  out.d3 = 3.0 * (inv3[0] * ddn2[0] - inv3[1] * ddn2[1]);
  return out;
}

/// Cubic B-spline basis function N_R(t) on the local knot vector r (Cox-de Boor, 0/0 := 0).
/// Zero outside the support; see RightEnd for t = r4. Inline, no allocation.
inline double cubic_basis(const LocalKnots& r, double t, RightEnd end = RightEnd::Open) {
  const int j = cubic_basis_interval(r, t, end);
  return j < 0 ? 0.0 : cubic_basis_piece_value(r, j, t);
}

/// N_R(t) and its first three derivatives (right derivatives at interior knots, left
/// derivatives at t = r4 with RightEnd::Closed). All zero outside the support.
inline BasisDerivatives cubic_basis_derivatives(const LocalKnots& r, double t,
                                                RightEnd end = RightEnd::Open) {
  const int j = cubic_basis_interval(r, t, end);
  return j < 0 ? BasisDerivatives{} : cubic_basis_piece_derivatives(r, j, t);
}

/// True if r is a usable knot vector: finite, non-decreasing and r0 < r4.
bool local_knots_valid(const LocalKnots& r);

}  // namespace volspline::spline
