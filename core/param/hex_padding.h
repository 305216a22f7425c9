// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::param {

/// Hexes of any connectivity over shared nodes: hex h's node q sits at offset (q&1, q>>1&1,
/// q>>2&1) of the hex (the order of untangle_hex_mesh and mesh::hex_min_scaled_jacobian).
struct HexMesh {
  mesh::Positions xyz;                    ///< nodes, model units
  std::vector<std::array<int, 8>> hexes;  ///< node ids into xyz
  std::vector<int> hex_group;             ///< per hex, e.g. its cuboid
  std::vector<char> padding;              ///< per hex: 1 if it belongs to the padding layer
  std::vector<char> on_surface;           ///< per node: 1 if it lies on the solid's surface
  std::vector<int> copy_of;               ///< per node: the surface node it copies (pad_hex_mesh), or −1; empty = none
};

/// Inserts one layer of hexes under the surface (the padding of polycube hex meshing, Gregson et
/// al. 2011, Fu et al. 2016). A polycube map sends a cube edge onto the smooth surface, where the
/// hex along it has two faces on the surface at an angle near 180° and a corner Jacobian near or
/// below 0 whatever the interior nodes do; after padding every surface edge is shared by the
/// padding hexes of both faces, which split that angle. Every node on a surface face gets an inner
/// copy, placed `depth` of the way from the node to the mean centroid of its hexes; the input
/// hexes use the copies, and each surface face gains the hex between it and its copies (of the
/// group of the hex it came from). surface_faces[h]: bit f set if face f of hex h (axis f/2, the
/// face of nodes with that offset bit = f%2) lies on the surface. depth in (0, 1).
/// The result lists the input nodes first (same rows), then the copies; the input hexes first,
/// then the padding hexes, in the order of their hex and face.
HexMesh pad_hex_mesh(const mesh::Positions& xyz, const std::vector<std::array<int, 8>>& hexes,
                     const std::vector<int>& hex_group, const std::vector<std::uint8_t>& surface_faces, double depth);

/// Count of hexes with a corner scaled Jacobian ≤ 0 and the least corner scaled Jacobian.
struct HexMeshQuality {
  int num_inverted = 0;
  double min_scaled_jacobian = 1.0;
};
HexMeshQuality hex_mesh_quality(const HexMesh& mesh);

}  // namespace volspline::param
