// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/mesh/triangle_mesh.h"

namespace volspline::io {

/// Parses Wavefront OBJ text: `v x y z [w] [r g b]` and `f` lines whose corners are `i`, `i/t`,
/// `i//n` or `i/t/n` (1-based, or negative = relative to the vertices read so far); polygons are
/// fan-triangulated; `#` comments and all other statements are ignored.
/// Throws volspline::Error "name:line: problem" on a bad number, NaN/Inf coordinate, index 0 or
/// out of range, a face with fewer than 3 corners; "name: no faces" when there are none.
mesh::TriangleMesh parse_obj(const std::string& bytes, const std::string& name);

/// OBJ text of the mesh: one `v` line per vertex at round-trip precision, one `f` per triangle.
std::string serialize_obj(const mesh::TriangleMesh& mesh);

}  // namespace volspline::io
