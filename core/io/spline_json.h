// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/spline/tspline.h"

namespace volspline::io {

/// Serializes a T-spline as JSON (schema "volspline-tspline", version 1; see README "Spline
/// JSON schema"): one blending function per line with its 3 local knot vectors, weight and
/// control point, numbers at shortest round-trip precision. Deterministic: the same spline
/// gives the same bytes, and serialize(parse(text)) == text for any text this wrote.
std::string serialize_spline_json(const spline::TSpline& spline);

/// Parses a T-spline JSON document. `name` (a path or upload name) prefixes error messages.
/// Throws volspline::Error naming `name` and the offending field or function on: invalid JSON,
/// wrong format/version, missing or mistyped fields, knot vectors that are not 5 finite
/// non-decreasing numbers, non-positive weights, points of the wrong dimension (also everything
/// the TSpline constructor rejects).
spline::TSpline parse_spline_json(const std::string& text, const std::string& name);

/// Reads a spline JSON file. Throws like parse_spline_json and if the file cannot be read.
spline::TSpline read_spline_json(const std::string& path);

/// Writes a spline JSON file atomically. Throws volspline::Error naming the path on failure.
void write_spline_json(const std::string& path, const spline::TSpline& spline);

}  // namespace volspline::io
