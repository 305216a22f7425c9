// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/spline/gpc_spline.h"

namespace volspline::io {

/// A GPC spline as UTF-8 JSON ("format": "volspline-gpc-spline", schema in the README): the
/// domain (serialize_gpc_domain's object), the knot intervals per cuboid (and the knot lines where
/// they are not uniform), the clamped interfaces,
/// the dimension and the global control points (numbers at shortest round-trip precision).
/// The functions follow from the domain and the intervals (GpcSpline's construction is
/// deterministic), so write → read → write is byte-identical.
std::string serialize_gpc_spline_json(const spline::GpcSpline& spline);
/// True if `text` is a JSON object whose "format" is "volspline-gpc-spline" (a cheap check on the
/// first bytes: it does not validate the rest).
bool is_gpc_spline_json(const std::string& text);
/// Parses serialize_gpc_spline_json's output. Throws volspline::Error naming `source` and the
/// problem (not JSON, wrong format or version, a bad domain, intervals or points that do not fit
/// the functions, non-finite numbers).
spline::GpcSpline parse_gpc_spline_json(const std::string& text, const std::string& source);

/// VTU (appended, zlib) of every cuboid's boundary-to-boundary sampled hexes: cells³ straight
/// hexes per unit of the longest cuboid size (at least 1 per axis), nodes F at the lattice, cell
/// data `cuboid` and `scaled_jacobian` (the least of the 8 corners' scaled Jacobians of F's own
/// Jacobian, so a fold shows where the spline folds, not where the straight hex does).
std::string serialize_gpc_spline_vtu(const spline::GpcSpline& spline, int cells);

/// GLB of the spline's boundary: every Surface face of every cuboid tessellated at `samples`²
/// points, coloured by cuboid (io::segment_colour), with `lines` iso-parameter lines per axis per
/// face as line segments. Opens in Blender and three.js.
std::string serialize_gpc_spline_glb(const spline::GpcSpline& spline, int samples = 33, int lines = 9);

}  // namespace volspline::io
