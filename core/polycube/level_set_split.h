// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::polycube {

/// A triangle mesh refined so that a level set of a vertex function runs along its edges.
struct LevelSetSplit {
  mesh::TriangleMesh mesh;        ///< the same surface, more triangles
  std::vector<double> value;      ///< per vertex; exactly `level` on the level set
  std::vector<int> parent_face;   ///< per face, the face of the input it lies in
};

/// Inserts the level set {value = level} of a piecewise-linear vertex function into the mesh:
/// every edge whose ends lie strictly on opposite sides gets a vertex at the linear crossing, and
/// each crossed triangle is split into 2 or 3 (the quad's shorter diagonal). A vertex closer to
/// the level than `snap` times the value span of a crossing edge is put on the level instead (its
/// value becomes `level`, its position stays), unless a neighbour already is on it, so no sliver
/// thinner than `snap` of an edge appears and no triangle lies flat in the level set.
/// Orientation and positions of the input are kept; `parent_face` composes with the input's.
/// Preconditions: value.size() == positions rows, parent.size() == faces (or empty), 0 ≤ snap < 0.5.
LevelSetSplit split_at_level(const mesh::TriangleMesh& mesh, const std::vector<double>& value,
                             const std::vector<int>& parent, double level, double snap = 0.05);

}  // namespace volspline::polycube
