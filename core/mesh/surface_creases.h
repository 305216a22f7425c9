// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::mesh {

/// Triangles next to a crease of a triangle soup or mesh: per triangle, 1 if one of its vertices
/// lies on an edge (two triangles sharing the same two vertex ids) whose triangles' unit normals
/// make an angle above angle_rad (or where either normal is undefined: a zero-area triangle).
/// Edges with one triangle or more than two are not creases. angle_rad in [0, π].
std::vector<char> crease_triangles(const TriangleMesh& surface, double angle_rad);

}  // namespace volspline::mesh
