// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/mesh/halfedge_mesh.h"
#include "core/polycube/cuboid_layout.h"

namespace volspline::polycube {

/// One of the 4 cuboids of a T-shape, on the pants mesh.
struct TShapeCuboid {
  std::vector<int> faces;  ///< pants faces it covers
  /// Closing discs: vertex cycles (pants ids) oriented so that a disc whose halfedges run in cycle
  /// order closes the cuboid (triangulate_interface_disc's convention).
  std::vector<std::vector<int>> discs;
  std::array<int, num_cube_corners> corners{};            ///< pants vertex ids
  std::array<std::vector<int>, num_cube_edges> poly_edges;  ///< pants vertex paths
  /// Per cube face: −1 on the surface, k in 0..2 on the pants's boundary loop k, 3 + j on the
  /// inner disc J_j between the centre cuboid and arm j.
  std::array<int, 6> face_role{-1, -1, -1, -1, -1, -1};
};

/// T-to-cube of one pants (§3.3.2, Algorithm 3, Fig. 3.7): cuboid 0 is the centre C, cuboid
/// 1 + j the arm at boundary loop arm_loop[j]; C's faces x = 0, x = 1, z = 0 are glued to arms 0, 1,
/// 2 (face 5 of each arm, whose face 4 is its boundary loop).
struct TShapeLayout {
  std::array<TShapeCuboid, 4> cuboids;
  std::array<int, 3> arm_loop{};  ///< boundary loop index (0..2) of each arm
  /// The two concave edges (Type-1 ill-points) as their end vertices (pants ids).
  std::array<std::array<int, 2>, 2> concave_edges{};
};

/// Where lay_out_t_shape puts the centre's concave corners.
struct TShapeLayoutOptions {
  /// Their graph distance from the stem loop as a fraction of the crotch's (the top seams' lowest
  /// point), in (0, 1]: below 1 the centre reaches further down the stem, taller than the crotch
  /// alone makes it.
  double concave_corner_height = 1.0;
};

/// Cuts a pants into a centre cuboid and three arms. Deviation from Algorithm 3's three cylinder
/// cuts: the pants is cut by 6 disjoint seams between the 12 loop corners (every loop's two
/// opposite rim arcs face the other two loops; of the 64 choices the valid one with the
/// shortest seams wins) into two hexagons (front and back) and three strips (rims); the top rim
/// is the longest; the concave corners sit at the seams' midpoints on the other two rims, the
/// centre's top corners at a third and two thirds of the top seams; the centre's 10 inner edges
/// are straight chords of the hexagons and rims inserted into the mesh (cut_disc_chords), so the
/// 4 regions are discs bounded in cube order by construction (checked again by
/// complete_cuboid_layout).
/// `pants_mesh` is refined in place where the chords cross its faces (its boundary loops keep
/// their vertices); `face_origin` (per face) and `vertex_value` (per vertex) are extended over
/// the new faces (the origin of the face they split) and vertices (linear along the split edge).
/// `loops[k]`: boundary loop k as pants vertex ids in loop order; `piece_forward[k]`: the pants's
/// halfedges run along loop k in loop order; `corners[k]`: 4 ascending indices into loops[k].
/// `vertex_identity` (per pants vertex, or empty): equal for the two copies of a vertex of a cut
/// whose both sides bound the pants; then the seams between those two loops join each corner to
/// its own copy where possible (no twist around the handle).
/// `options`: how far down the stem the concave corners sit.
/// Returns false with the reason in *why.
bool lay_out_t_shape(mesh::TriangleMesh& pants_mesh, std::vector<int>& face_origin, std::vector<double>& vertex_value,
                     const std::array<std::vector<int>, 3>& loops, const std::array<bool, 3>& piece_forward,
                     const std::array<std::array<int, 4>, 3>& corners, const std::vector<int>& vertex_identity,
                     TShapeLayout& out, std::string* why, const TShapeLayoutOptions& options = {});

}  // namespace volspline::polycube
