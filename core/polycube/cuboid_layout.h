// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include "core/common/progress.h"
#include "core/mesh/halfedge_mesh.h"

namespace volspline::polycube {

/// Corner c of the unit cube sits at (u, v, w) = (c & 1, (c >> 1) & 1, (c >> 2) & 1).
inline constexpr int num_cube_corners = 8;
/// Cube edge e runs along axis e / 4 from its corner with that bit 0 to the one with it 1.
inline constexpr int num_cube_edges = 12;
/// Cube face f lies on the plane (axis f / 2) = (f % 2).
inline constexpr int num_cube_faces = 6;

/// Corner ids (low, high) of cube edge e (0..11).
std::array<int, 2> cube_edge_corners(int edge);
/// The cube edge joining two corners that differ in exactly one bit (asserts so).
int cube_edge_between(int corner_a, int corner_b);
/// The 4 corners of cube face f (0..5) in cyclic order around the face.
std::array<int, 4> cube_face_corners(int face);
/// The 4 edges of cube face f (0..5).
std::array<int, 4> cube_face_edges(int face);

/// A closed genus-0 surface cut into 6 topological rectangles (thesis §3.4.1, Fig. 3.8(a)):
/// 8 corner vertices and 12 vertex-disjoint poly-edges along mesh edges.
struct CuboidLayout {
  std::array<int, num_cube_corners> corners{};  ///< mesh vertex id of each cube corner
  /// Vertex path of each cube edge, from cube_edge_corners(e)[0] to [1]; paths share only
  /// their end corners.
  std::array<std::vector<int>, num_cube_edges> poly_edges;
  std::vector<int> face_region;  ///< per mesh face: cube face id 0..5
  double min_corner_distance_rel = 0.0;  ///< closest corner pair / bounding-box diagonal
};

/// Options of compute_cuboid_layout.
struct CuboidLayoutOptions {
  /// Corner vertex ids in cube-corner order (see num_cube_corners); empty = automatic choice.
  std::vector<int> corners;
};

/// Lays a cuboid onto a closed genus-0 mesh.
///
/// Automatic corners: in a right-handed, area-weighted PCA frame and 39 fixed rotations of it
/// (each refined by Procrustes fits of the box to its corners), the vertices extremal in the 8
/// diagonal directions scaled by the principal extents; the frame whose corners are farthest
/// apart (no slivers) wins. Only the shape matters, not its pose. If those corners cannot be
/// laid out, the vertices nearest to the box corners are tried instead.
/// Poly-edges: Dijkstra shortest paths, made disjoint by forbidding used vertices: first the
/// two loops around the ends of the longest cube axis, then the 4 long edges inside the annulus
/// between the loops, so the 12 paths always cut the sphere into 6 disks in cube order.
/// progress: "cuboid layout" with the fraction done (candidate frames, then band axes tried).
/// Preconditions: a closed, consistently oriented, connected genus-0 mesh (checked by caller).
/// Throws volspline::Error naming the mesh when user corners are invalid (wrong count, out of
/// range, repeated, mirrored order) or when no valid layout is found; volspline::Cancelled if
/// progress asks to stop.
CuboidLayout compute_cuboid_layout(const mesh::HalfedgeMesh& mesh,
                                   const CuboidLayoutOptions& options = {}, const Progress& progress = {});

/// The automatic layouts of compute_cuboid_layout, in its order of preference: the corner sets
/// of the candidate frames that can be laid out (distinct sets, extremal rule first), up to
/// max_layouts (≥ 1); the first is compute_cuboid_layout's. A caller that can measure the
/// layouts (e.g. by their surface maps) picks among them. Throws like compute_cuboid_layout
/// when none can be laid out; progress as there.
std::vector<CuboidLayout> candidate_cuboid_layouts(const mesh::HalfedgeMesh& mesh, int max_layouts,
                                                   const Progress& progress = {});

/// Completes a layout whose 8 corners are set (layout.corners): the 4 poly-edges around each end
/// face of `band_axis` (cube faces 2·band_axis and 2·band_axis + 1) first, then the 4 edges along
/// the band between them, each a Dijkstra shortest path avoiding the vertices already used unless
/// `fixed[e]` prescribes it (a vertex path from cube_edge_corners(e)[0] to [1]). Used for the
/// cuboids of a GPC, whose faces glued to other cuboids have prescribed boundaries.
/// `band_cost` (per edge, ≥ 0; null = edge lengths) weighs the band paths, e.g. lengths in a
/// cylinder parameterization so that they run straight along a tube.
/// Returns false with the reason in *why (may be null) if the paths do not cut the surface into
/// 6 discs in cube order. Precondition: a closed genus-0 mesh; corners distinct.
bool complete_cuboid_layout(const mesh::HalfedgeMesh& mesh, int band_axis,
                            const std::array<std::vector<int>, num_cube_edges>& fixed, CuboidLayout& layout,
                            std::string* why, const std::vector<double>* band_cost = nullptr);

}  // namespace volspline::polycube
