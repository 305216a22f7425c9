// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/common/progress.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/polycube/cube_faces.h"
#include "core/polycube/cuboid_layout.h"

namespace volspline::param {

/// Edge weights of the per-rectangle harmonic maps.
enum class SurfaceWeights {
  MeanValue,  ///< Floater's mean-value weights, symmetrized; always > 0, so the map is bijective
  Cotan,      ///< cotangent weights; can be negative on obtuse meshes (checked for flips)
};

/// Preconditioner of the conjugate-gradient solves of the rectangles' maps.
enum class SurfaceSolver {
  Multigrid,           ///< smoothed-aggregation AMG: about constant iterations, O(n) per solve
  IncompleteCholesky,  ///< IC(0): iterations grow like √n, O(n^1.5) per solve
};

/// Options of compute_cuboid_surface_map.
struct CuboidSurfaceMapOptions {
  SurfaceWeights weights = SurfaceWeights::MeanValue;
  double tolerance = 1e-10;  ///< relative CG residual of the final solves (unitless), in (0, 1)
  /// Relative CG residual of the solves of the area-balancing rounds before the last, in
  /// [tolerance, 1): their maps only set the next round's weights (1e-8 leaves the harmonic gpc
  /// grids of the shared meshes with the same inverted hexes, minimum scaled Jacobians within
  /// 1e-5).
  double balance_tolerance = 1e-8;
  /// Stretch-reweighting rounds that give squeezed parts more parameter area (0 = the plain
  /// Tutte/Floater map), in [0, 20]; every round is still a convex-combination map.
  int area_balance_iterations = 0;
  /// Squeeze rescue after those rounds: while some vertex inside a rectangle has a linear
  /// parameter density √(parameter share / surface share of its cube face) below squeezed_below,
  /// rounds that only widen squeezed parts, up to squeezed_rounds; in [0, 1), 0 = off. Thin tips
  /// (ears, tails, claws) left crowded into a spot no spline cell resolves get room; a map
  /// above the bound is unchanged.
  double squeezed_below = 0.0;
  int squeezed_rounds = 20;  ///< in [0, 40]
  SurfaceSolver solver = SurfaceSolver::Multigrid;
};

/// Map of a closed genus-0 surface onto the boundary of the unit cube (thesis §3.4.1).
struct CuboidSurfaceMap {
  mesh::Positions uvw;           ///< per mesh vertex, a point on the boundary of [0,1]³
  std::vector<int> face_region;  ///< per mesh face, cube face id 0..5 (see polycube)
  int num_flipped = 0;  ///< triangles with non-positive oriented area in their cube face
  int cg_iterations = 0;  ///< largest CG iteration count over the 6 faces
  int squeeze_rounds = 0;  ///< squeeze rescue rounds run (CuboidSurfaceMapOptions::squeezed_below)
  /// Least linear parameter density of a vertex inside a rectangle (see squeezed_below) in the
  /// final map; +inf without such vertices.
  double least_density = 0.0;
  /// The same before the squeeze rescue (the area-balanced map).
  double unrescued_least_density = 0.0;
};

/// Whether a surface map is squeezed: the rescue ran (squeeze_rounds > 0) or a vertex's linear
/// parameter density stays below `below` (CuboidSurfaceMapOptions::squeezed_below), i.e. a tip
/// crowded into a spot of a cube face. One rule for every job that acts on it.
inline bool squeezed_map(int squeeze_rounds, double least_density, double below) {
  return squeeze_rounds > 0 || least_density < below;
}

/// The cube-face coordinates of the surface map (polycube/cube_faces.h).
using polycube::cube_face_coordinates;
using polycube::cube_face_point;

/// Parameterizes the 6 rectangles of a cuboid layout.
///
/// Deviation from §3.4.1 (three global harmonic solves Δu = Δv = Δw = 0 with opposite
/// rectangles pinned at 0 and 1): each rectangle is mapped on its own to its unit square with
/// the poly-edges fixed by arc length and a discrete harmonic interior; with positive weights
/// this is Tutte/Floater's convex-combination map, which is provably bijective, and shared
/// poly-edges get the same parameters from both sides, so the 6 maps glue continuously.
/// Throws volspline::Error on options out of range, and naming the mesh, the cube face and the
/// first bad triangle if the map is not bijective (flipped or degenerate triangles, e.g. cotan
/// weights on a bad mesh); volspline::Cancelled if progress asks to stop.
/// progress: "surface map" with the fraction of face solves done (6 per balancing round + 1).
CuboidSurfaceMap compute_cuboid_surface_map(const mesh::HalfedgeMesh& mesh,
                                            const polycube::CuboidLayout& layout,
                                            const CuboidSurfaceMapOptions& options = {},
                                            const Progress& progress = {});

}  // namespace volspline::param
