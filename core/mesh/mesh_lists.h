// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"

namespace volspline::mesh {

/// The n×3 positions of a point list: row v is points[v].
Positions positions_from(const std::vector<Eigen::Vector3d>& points);

/// The m×3 triangles of a list of vertex id triples: row t is tris[t] (ids are not checked).
Triangles triangles_from(const std::vector<std::array<int, 3>>& tris);

/// Midpoint vertex ids of split edges, keyed by (smaller, larger) end vertex id.
using EdgeMidpoints = std::map<std::pair<int, int>, int>;

/// `tri` split at the midpoints of those of its edges listed in `midpoint` (ids ≥ first_midpoint),
/// with `tri`'s orientation: the corners between two midpoints cut off first, then the rest
/// fanned from a corner. A triangle with no split edge is returned as it is (one part).
std::vector<std::array<int, 3>> split_at_midpoints(const std::array<int, 3>& tri, const EdgeMidpoints& midpoint,
                                                   int first_midpoint);

}  // namespace volspline::mesh
