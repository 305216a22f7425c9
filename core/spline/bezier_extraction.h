// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/spline/tspline.h"

namespace volspline::spline {

/// Bernstein (Bézier) form of one knot-line cell of a TSpline: on a cell every blending function
/// is one tricubic polynomial, so F is one too (Eq. 4.3), and its 4×4×4 Bernstein control net
/// represents it exactly. Net entry (i, j, k) (i along u) sits at net index i + 4·j + 16·k.
/// Local coordinates s ∈ [0, 1]³ map to uvw = uvw_min + s ⊙ (uvw_max − uvw_min).
struct BezierCell {
  int cell = 0;                       ///< TSpline cell id (TSpline::cell_index gives its grid interval)
  Eigen::Vector3d uvw_min = Eigen::Vector3d::Zero();  ///< lower corner of the cell box
  Eigen::Vector3d uvw_max = Eigen::Vector3d::Zero();  ///< upper corner of the cell box
  int dimension = 0;                  ///< D, components of F
  /// Bernstein coefficients of the semi-standard numerator Σ w_i p_i B_i: entry (net index)·D + d.
  /// This is F as TSplineForm::SemiStandard evaluates it (a polynomial Bézier cell).
  std::array<double, 64 * 4> points{};
  /// Bernstein coefficients of Σ w_i B_i (all 1 to rounding for a semi-standard spline). The
  /// rational form (Eq. 4.1) is the rational Bézier cell with control points points/weights and
  /// these weights (all > 0: they are sums of the B_i's non-negative Bernstein coefficients).
  std::array<double, 64> weights{};
};

/// Converts power-form coefficients of a tricubic polynomial (monomial m = (4a + b)·4 + c of
/// s_u^a s_v^b s_w^c, `channels` values each, as TSpline::cell_power_form) to Bernstein
/// coefficients at net index i + 4j + 16k, `channels` values each: per axis the fixed basis change
/// b_i = Σ_{a ≤ i} C(i, a)/C(3, a)·c_a. Precondition: channels in 1..4.
void power_to_bernstein(const double* power, int channels, double* bernstein);

/// The Bézier cell of TSpline cell `cell` (0 <= cell < spline.num_cells()). Exact to rounding.
BezierCell extract_bezier_cell(const TSpline& spline, int cell);

/// Every cell of the spline's knot-line grid, in cell order (u fastest). Per single-patch
/// TSpline: a multi-cuboid spline calls it once per cuboid.
std::vector<BezierCell> extract_bezier_cells(const TSpline& spline);

/// Cubic Bernstein values B_0..B_3 at t and, if derivative is non-null, their derivatives.
void cubic_bernstein(double t, double* value, double* derivative = nullptr);

/// The semi-standard F of a Bézier cell at local coordinates s ∈ [0, 1]³ (value[0..D)) and, if
/// jacobian is non-null, its D×3 Jacobian with respect to uvw (column-major, as TSpline).
void evaluate_bezier_cell(const BezierCell& cell, const Eigen::Vector3d& s, double* value,
                          double* jacobian = nullptr);

}  // namespace volspline::spline
