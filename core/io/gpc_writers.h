// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"

namespace volspline::io {

/// Hexes over shared nodes: hex h's node q at offset (q&1, q>>1&1, q>>2&1) of the hex.
struct HexMeshView {
  const mesh::Positions* xyz = nullptr;                    ///< nodes, model units
  const std::vector<std::array<int, 8>>* hexes = nullptr;  ///< node ids into xyz
  const std::vector<int>* cuboid = nullptr;                ///< per hex
  const std::vector<char>* padding = nullptr;              ///< per hex, 1 in a padding layer; or null
  /// per hex, the cell data `scaled_jacobian`; null = the least corner scaled Jacobian of the hex
  const std::vector<double>* scaled_jacobian = nullptr;
};

/// The hexes as one VTK XML UnstructuredGrid (.vtu, VtkXmlWriter's appended binary, zlib where
/// the build has it; VTK_HEXAHEDRON, every node once) with cell data "cuboid", "scaled_jacobian"
/// (smallest corner scaled Jacobian of the hex, in [−1, 1]) and, if given, "padding" (0/1).
std::string serialize_hex_mesh_vtu(const HexMeshView& mesh);

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
