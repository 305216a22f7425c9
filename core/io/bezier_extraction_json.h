// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/spline/gpc_spline.h"
#include "core/spline/tspline.h"

namespace volspline::io {

/// The Bézier extraction operator of a spline in JSON (the IGA exchange form: per element the
/// global control points it uses and the matrix taking the cubic Bernstein basis of the element
/// to their blending functions). Keys: `format` "volspline-bezier-extraction", `version` 1,
/// `form` "semi-standard" (F = Σ w_i p_i B_i, Eq. 4.3), `degree` [3,3,3], `dimension` D,
/// `control_points` (n rows of D), `weights` (n), `univariate` (rows [b0,b1,b2,b3]: the
/// Bernstein coefficients of one cubic B-spline piece on one cell interval, shared), `cells`
/// (per knot-line cell: `cuboid`, `uvw_min`, `uvw_max` in that cuboid's coordinates,
/// `functions` (global ids), `extraction` (per function [iu, iv, iw], rows of `univariate`)).
/// The extraction matrix of a cell is C[f][i + 4j + 16k] = U[iu][i]·U[iv][j]·U[iw][k] (a
/// blending function is a tensor product, Eq. 4.2), B_f = Σ_m C[f][m] Bernstein_m(s) on the
/// cell's local coordinates s = (uvw − uvw_min)/(uvw_max − uvw_min). Deterministic bytes.
std::string serialize_bezier_extraction_json(const spline::TSpline& spline);

/// The same for a GPC spline: the cells of every cuboid's box (its patch's cells outside the
/// box, where a face is Continued, belong to the neighbour), global function ids.
std::string serialize_bezier_extraction_json(const spline::GpcSpline& spline);

}  // namespace volspline::io
