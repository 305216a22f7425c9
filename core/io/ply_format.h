// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/mesh/triangle_mesh.h"

namespace volspline::io {

/// Parses PLY (ascii, binary_little_endian, binary_big_endian 1.0). Vertex positions come from
/// the `x`, `y`, `z` properties of element `vertex` (any scalar type); faces from the list
/// property `vertex_indices` (or `vertex_index`) of element `face` with any count and index type,
/// fan-triangulated. Other properties and elements are skipped.
/// Throws volspline::Error naming `name` and the header line or element on: a bad header,
/// counts larger than the data can hold (checked before allocating), truncated data, NaN/Inf,
/// indices out of range or not integers, faces with fewer than 3 vertices, no faces.
mesh::TriangleMesh parse_ply(const std::string& bytes, const std::string& name);

/// Binary little-endian PLY: double x, y, z; `list uchar int vertex_indices`. Exact round trip.
std::string serialize_ply(const mesh::TriangleMesh& mesh);

}  // namespace volspline::io
