// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include "core/common/progress.h"
#include "core/mesh/triangle_mesh.h"
#include "core/param/cuboid_surface_map.h"
#include "core/param/hex_padding.h"
#include "core/polycube/gpc_builder.h"

namespace volspline::param {

/// Options of compute_gpc_volumetric_map.
struct GpcGridOptions {
  int target_nodes = 24000;  ///< about this many grid nodes over all cuboids, ≥ 64
  int min_nodes = 5;         ///< per axis, ≥ 2
  int max_nodes = 96;        ///< per axis, ≥ min_nodes
  double tolerance = 1e-9;   ///< relative CG residual of the Laplacian solve (unitless)
  int area_balance_iterations = 4;  ///< of every cuboid's surface map (see CuboidSurfaceMapOptions)
  /// Squeeze rescue of every cuboid's surface map (CuboidSurfaceMapOptions::squeezed_below), in
  /// [0, 1); off here: the hex mesh's own quality stages are tuned on the balanced maps, and
  /// mesh2spline turns it on (GpcMesh2SplineOptions::squeezed_below).
  double squeezed_below = 0.0;
  enum class Untangle { Off, On } untangle = Untangle::On;  ///< remove hex folds (untangle_hex_grid)
  /// The output hex mesh: the cuboid grids as they are, or with a padding layer under the
  /// surface (pad_hex_mesh), untangled again with only the surface held.
  enum class Padding { Off, On } padding = Padding::On;
  double padding_depth = 0.5;  ///< pad_hex_mesh's depth, in (0, 1)
  int quality_iterations = 100;  ///< improve_hex_mesh on the padded mesh once fold-free (0: off)
  /// Where the padded mesh's untangling with the whole surface held leaves folds: untangled once
  /// more with the surface nodes inside an exposed cube face sliding on its patch (On), or left as
  /// they are (Off: every surface node stays where the surface maps put it, in the quality step
  /// after the untangling too, for a fit that samples each node at its grid parameter;
  /// pipeline::run_gpc keeps On where its limb
  /// constructions are chosen by their hex meshes' folds).
  enum class FaceSliding { Off, On } face_sliding = FaceSliding::On;
  /// The reference cell of the padded mesh's untanglers (HexGridUntangleOptions::reference):
  /// MeanCell, OwnCell, or Better: the mean cell, and where that leaves inverted hexes after the
  /// untanglers and improve_hex_mesh, the own cell too from the same start, kept if it leaves
  /// fewer (a tie keeps the mean cell's: the least value of a folded mesh says little of where
  /// the last stage ends).
  enum class PaddedReference { MeanCell, OwnCell, Better } padded_reference = PaddedReference::Better;
  /// raise_min_scaled_jacobian on the padded mesh, every surface node sliding on the whole surface
  /// except at creases: its hexes below this corner scaled Jacobian are worked on, in (−1, 1]
  double min_quality_target = 0.3;
  int min_quality_sweeps = 300;  ///< its sweeps at most (0: off, the padded mesh as improve_hex_mesh leaves it)
  /// The last stage's worst-spot relaxation, where a pass is not kept, is tried once more one ring
  /// of hexes wider while the least scaled Jacobian is below this (the try costs a raise over the
  /// whole mesh), in [−1, 1]; −1: never.
  double wider_relax_below = 0.2;
};

/// The grid of one cuboid: node (i, j, k) at row i + n0·(j + n1·k), parameter (i/(n0−1), …).
struct GpcCuboidGrid {
  std::array<int, 3> nodes{};
  mesh::Positions xyz;
  int num_hexes = 0;
  int num_inverted_hexes = 0;
  double min_scaled_jacobian = 1.0;
};

/// The volumetric parameterization of a GPC (§3.4): surface maps and node grids of all cuboids.
struct GpcVolumetricMap {
  std::vector<CuboidSurfaceMap> surface_maps;  ///< per cuboid, on its CuboidSurface::mesh
  std::vector<GpcCuboidGrid> grids;            ///< per cuboid
  /// The hex mesh of the solid: every cuboid grid's hexes over shared nodes (hex_group = cuboid),
  /// with the padding layer if GpcGridOptions::padding is On.
  HexMesh hex_mesh;
  int flipped_triangles = 0;         ///< over all surface maps (0: every map bijective)
  int grid_inverted_hexes = 0;       ///< hexes of hex_mesh with a corner Jacobian ≤ 0
  double grid_min_scaled_jacobian = 1.0;  ///< least corner scaled Jacobian of hex_mesh
  int harmonic_inverted_hexes = 0;   ///< cuboid grid hexes with a corner Jacobian ≤ 0 before untangling
  int cuboid_grid_inverted_hexes = 0;       ///< the same after untangling (grids, no padding)
  double cuboid_grid_min_scaled_jacobian = 1.0;  ///< of the grids, no padding
  double interface_gap_rel = 0.0;    ///< largest distance between copies of a shared node / diagonal
  int shared_nodes = 0;              ///< nodes on glued faces (counted once)
  int untangled_nodes = 0;
  int cg_iterations = 0;
};

/// §3.4.1 per cuboid (compute_cuboid_surface_map on its closed surface), then §3.4.2 on all
/// cuboids at once: node counts from the cuboid sizes (the same along glued axes), boundary
/// nodes on the solid's surface by inverse lookup, the nodes of glued faces identified through
/// the transition maps (one node, so both sides agree exactly), and every other node placed by
/// the 6-neighbour Laplacian of Eq. 3.1 over the union of the grids, solved by CG. Solving across
/// the glued faces is the thesis's "boundary modification" (end of §3.4.2) done once for all
/// interfaces: the parameterization is smooth across them instead of pinned to the discs. Folded
/// hexes are then untangled per cuboid (untangle_hex_grid) with the shared nodes held, and the
/// folds left over all cuboids at once (untangle_hex_mesh) with the shared nodes free.
/// Writes the node counts into construction.domain.cuboids[c].nodes. `progress` hears the phases
/// ('surface map', 'volumetric map', 'grid untangling', 'padding', 'grid quality') with the fraction of this map done.
/// Throws polycube::DecompositionError naming the cuboid if a surface map is not bijective;
/// volspline::Cancelled if progress asks to stop.
GpcVolumetricMap compute_gpc_volumetric_map(polycube::GpcConstruction& construction, double bbox_diagonal,
                                            const GpcGridOptions& options = {}, const Progress& progress = {});

}  // namespace volspline::param
