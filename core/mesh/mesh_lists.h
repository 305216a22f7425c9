// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"

namespace volspline::mesh {

/// The n×3 positions of a point list: row v is points[v].
Positions positions_from(const std::vector<Eigen::Vector3d>& points);

/// The m×3 triangles of a list of vertex id triples: row t is tris[t] (ids are not checked).
Triangles triangles_from(const std::vector<std::array<int, 3>>& tris);

}  // namespace volspline::mesh
