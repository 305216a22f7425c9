// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::polycube {

/// A triangle mesh refined so that a level set of a vertex function runs along its edges.
struct LevelSetSplit {
  mesh::TriangleMesh mesh;        ///< the same surface, more triangles
  std::vector<double> value;      ///< per vertex; exactly `level` on the level set
  std::vector<int> parent_face;   ///< per face, the face of the input it lies in
  /// Per vertex added (id num_vertices() of the input + k): the input edge (a, b) it lies on and
  /// its parameter t there (position = (1 − t)·x_a + t·x_b), for other vertex data to follow.
  std::vector<std::array<int, 2>> new_vertex_edge;
  std::vector<double> new_vertex_t;
};

/// Inserts the level set {value = level} of a piecewise-linear vertex function into the mesh:
/// every edge whose ends lie strictly on opposite sides gets a vertex at the linear crossing, and
/// each crossed triangle is split into 2 or 3 (the quad's shorter diagonal). A vertex closer to
/// the level than `snap` times the value span of a crossing edge is put on the level instead (its
/// value becomes `level`, its position stays), unless a neighbour already is on it, so no sliver
/// thinner than `snap` of an edge appears and no triangle lies flat in the level set.
/// Orientation and positions of the input are kept; `parent_face` composes with the input's.
/// `frozen` (per vertex, or empty): vertices never snapped. The mesh may have a boundary (the
/// snapping test then sees a boundary vertex's one-ring partly; freeze the boundary to be safe).
/// Preconditions: value.size() == positions rows, parent.size() == faces (or empty), 0 ≤ snap < 0.5.
LevelSetSplit split_at_level(const mesh::TriangleMesh& mesh, const std::vector<double>& value,
                             const std::vector<int>& parent, double level, double snap = 0.05,
                             const std::vector<char>& frozen = {});

}  // namespace volspline::polycube
