// SPDX-License-Identifier: MIT
#pragma once

#include <memory>
#include <vector>

#include "core/mesh/halfedge_mesh.h"
#include "core/polycube/cuboid_layout.h"
#include "core/polycube/gpc_domain.h"
#include "core/polycube/interface_disc.h"
#include "core/polycube/solid_decomposition.h"
#include "core/polycube/t_shape_layout.h"

namespace volspline::polycube {

/// The closed genus-0 surface bounding one cuboid's part of the solid (its piece of the input
/// surface plus the interface discs of its glued faces) with its 8 corners and 12 poly-edges.
struct CuboidSurface {
  mesh::TriangleMesh mesh;          ///< outward oriented; positions model units
  CuboidLayout layout;              ///< on `mesh`
  std::vector<int> surface_vertex;  ///< per vertex: vertex of the decomposition mesh, −1 inside a disc
  std::vector<int> surface_face;    ///< per face: face of the decomposition mesh, −1 on a disc
  /// `mesh` with its halfedges as the layout saw them (the volumetric map reuses them), or null;
  /// run_gpc drops it when it scales `mesh` back to model units.
  std::shared_ptr<const mesh::HalfedgeMesh> halfedges;
};

/// A GPC with the surface of every cuboid.
struct GpcConstruction {
  GpcDomain domain;
  std::vector<CuboidSurface> surfaces;  ///< one per cuboid
  std::vector<InterfaceDisc> discs;     ///< one per cut loop (oriented to close the piece above)
  /// Per cut loop: its 4 corners as indices into CutLoop::vertices, in loop order.
  std::vector<std::array<int, 4>> loop_corners;
};

/// T-to-cube (§3.3.2, Algorithms 2, 3): a cap becomes 1 cuboid (its loop on face w = 0, the 4
/// upper corners halfway up the cap), a tube 1 cuboid (its loops on faces w = 0 and w = 1, the 4
/// band poly-edges the shortest disjoint paths between the loops' corners, over the 4 cyclic
/// matchings the shortest), a T-shape 4 cuboids. Every cut loop gets 4 corners at quarter arc
/// lengths from its vertex farthest from its centroid (a choice that does not depend on the
/// pose), shared by both sides, and one interface disc used by both. Cuboid sizes: one length per
/// class of axes glued together (union–find over the interfaces), the mean length of the class's
/// poly-edges over the bounding-box diagonal.
/// `solid_corners`: user corners of a genus-0 solid's one cuboid (compute_cuboid_layout's), or empty.
/// With `merge_cuboids`, cuboids glued end to end across a cut (their faces w = 1 and w = 0: arms,
/// tubes, caps) are merged into one while the union's surface is a sphere, repeatedly.
/// A T-shape's layout cuts run along new edges: `decomposition` is refined inside its T-shapes
/// (vertices and faces appended, each split face keeping its id for one part; loops unchanged).
/// `t_shape`: where every T-shape's centre puts its concave corners (lay_out_t_shape).
/// Throws DecompositionError naming the piece when a layout cannot be traced, volspline::Error
/// when user corners are invalid.
GpcConstruction build_gpc(SolidDecomposition& decomposition, double bbox_diagonal,
                          const std::vector<int>& solid_corners = {}, bool merge_cuboids = true,
                          const TShapeLayoutOptions& t_shape = {});

/// Splits at its midpoint every chord of a poly-edge inside a cuboid's surface faces (an edge
/// joining two vertices of one poly-edge that is not on it), in the cuboid's surface and in
/// `decomposition` alike: §3.4.1's Tutte map would put the region between the chord and the
/// poly-edge onto the straight side with zero area. build_gpc calls it last; a construction
/// without chords is unchanged. Disc triangles are left as they are (both sides share them).
void split_poly_edge_chords(SolidDecomposition& decomposition, GpcConstruction& construction);

/// How evenly the layout spreads the surface over the domain's faces (§3.4.1: the surface map
/// of a face is uniform only if its region and its domain face are alike): per cuboid face on
/// the surface, in cuboid then face order, the area share of its surface region (of the whole
/// surface) over the area share of its domain face (of all surface faces of the domain). 1 for
/// a balanced face; a sliver region on a wide face is far below 1 and crowds its grid nodes.
std::vector<double> face_area_ratios(const GpcConstruction& construction);

}  // namespace volspline::polycube
