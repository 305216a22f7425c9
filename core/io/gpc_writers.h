// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"

namespace volspline::io {

/// A structured hex grid: node (i, j, k) at row i + n0·(j + n1·k) of xyz (model units).
struct HexGridView {
  std::array<int, 3> nodes{};
  const mesh::Positions* xyz = nullptr;
};

/// Every grid's hexes as one VTK XML UnstructuredGrid (.vtu, VtkXmlWriter's appended binary,
/// zlib where the build has it; VTK_HEXAHEDRON) with cell
/// data "cuboid" (the grid's index) and "scaled_jacobian" (smallest corner scaled Jacobian of the
/// hex, in [−1, 1]). Nodes shared between grids are written once per grid.
std::string serialize_hex_grids_vtu(const std::vector<HexGridView>& grids);
void write_hex_grids_vtu(const std::string& path, const std::vector<HexGridView>& grids);

/// The colour of segment s ≥ 0 in serialize_segmented_glb: RGB, components in [0.25, 0.95], the
/// hues spread by the golden angle so that consecutive ids differ strongly.
std::array<float, 3> segment_colour(int s);

/// GLB (binary glTF 2.0) of a segmented surface: the triangles coloured by segment (vertex
/// colours, one per face corner so segments have sharp borders, with flat normals), the given
/// polylines as line segments and the given points (e.g. corners) as a point primitive. Opens in
/// Blender and three.js. face_segment: per triangle, ≥ 0.
std::string serialize_segmented_glb(const mesh::TriangleMesh& surface, const std::vector<int>& face_segment,
                                    const std::vector<std::vector<Eigen::Vector3d>>& polylines,
                                    const std::vector<Eigen::Vector3d>& points);
void write_segmented_glb(const std::string& path, const mesh::TriangleMesh& surface,
                         const std::vector<int>& face_segment,
                         const std::vector<std::vector<Eigen::Vector3d>>& polylines,
                         const std::vector<Eigen::Vector3d>& points);

}  // namespace volspline::io
