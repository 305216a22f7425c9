// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/spline/bspline_multipatch.h"

namespace volspline::io {

/// G+Smo XML of a multipatch (gsMultiPatch): one `<Geometry type="TensorBSpline3" id="p">` per
/// patch (a `TensorBSplineBasis3` of three `BSplineBasis` with their `<KnotVector degree="3">`,
/// `<coefs geoDim="D">` one control point per line, u fastest), then `<MultiPatch parDim="3">`
/// with `<patches type="id_range">0 P−1</patches>`, `<interfaces>` (per line: patch side patch
/// side, the direction map and the orientation flags, G+Smo sides 1..6 = cube face + 1: west,
/// east, south, north, front, back) and `<boundary>` (patch side per line). Numbers at
/// round-trip precision; deterministic bytes.
std::string serialize_gismo_xml(const spline::BsplineMultipatch& multipatch);

}  // namespace volspline::io
