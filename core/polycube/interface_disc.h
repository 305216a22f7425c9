// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::polycube {

/// A triangulated disc spanning a cut loop inside the solid: the interface between the two
/// pieces on either side of the loop, shared by both (§3.3, the "cutting hole" filling).
struct InterfaceDisc {
  /// The loop's m vertices first (in loop order), then the interior vertices; model units.
  mesh::Positions positions;
  /// Oriented so that the disc's halfedges run along the loop in loop order (it closes the
  /// piece above the loop with its normal pointing below); reverse for the piece below.
  mesh::Triangles triangles;
  int num_loop_vertices = 0;
};

/// Concentric rings around the loop's centroid (ring count about the loop's length / 2π, at most
/// 12), joined by quad strips split into triangles, then the interior placed by a discrete
/// harmonic (uniform Laplacian) extension of the loop: a minimal-surface-like disc. No triangle
/// has three loop vertices and every loop edge is in exactly one triangle, so a convex-combination
/// map of the disc to a square is bijective. Precondition: m ≥ 3.
InterfaceDisc triangulate_interface_disc(const mesh::Positions& loop_xyz);

/// Result of check_interface_discs.
struct DiscEmbedding {
  int num_intersections = 0;   ///< disc–surface and disc–disc triangle pairs that cross
  int num_outside = 0;         ///< discs whose centre has winding number < 1/2 (outside the solid)
  std::vector<double> winding; ///< per disc, the generalized winding number of its centre
  std::vector<int> crossings;  ///< per disc, its triangle pairs that cross (with the surface or a later disc)
  std::string first_problem;   ///< empty when embedded
};

/// Meridian certificate (§3.3.1: a cut must bound a disc inside the solid): a loop bounds an
/// embedded disc in the solid iff some disc spanning it meets the surface only along the loop
/// and lies inside. Checks every disc triangle against every surface triangle and the other
/// discs' triangles that share no vertex with it (segment–triangle crossings of the 6 edges,
/// on a uniform bucket grid), and the centre's winding number (solid angles, inside ≈ 1).
/// `loop_ids[d]` lists the surface vertex id of each of disc d's loop vertices.
/// Coplanar touching pairs are not counted (they need exact predicates).
DiscEmbedding check_interface_discs(const mesh::TriangleMesh& surface, const std::vector<InterfaceDisc>& discs,
                                    const std::vector<std::vector<int>>& loop_ids);

/// The meridian certificate of one loop of `surface` (vertex ids in loop order, ≥ 3): its
/// triangulate_interface_disc disc checked against the surface by check_interface_discs.
DiscEmbedding check_loop_disc(const mesh::TriangleMesh& surface, const std::vector<int>& loop);

}  // namespace volspline::polycube
