// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/mesh/triangle_mesh.h"

namespace volspline::io {

/// Parses OFF text (header `OFF`, `COFF`, `NOFF`, `STOFF`..., counts on the header line or the
/// next one), `#` comments anywhere, vertex lines `x y z [extra columns ignored]`, face lines
/// `n i1 .. in [colour ignored]` (0-based; polygons fan-triangulated).
/// Throws volspline::Error "name:line: problem" on a bad header, negative or huge counts,
/// truncation, bad numbers, NaN/Inf, indices out of range; "name: no faces" when F is 0.
mesh::TriangleMesh parse_off(const std::string& bytes, const std::string& name);

/// OFF text of the mesh at round-trip precision.
std::string serialize_off(const mesh::TriangleMesh& mesh);

}  // namespace volspline::io
