// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

#include "core/common/progress.h"
#include "core/mesh/triangle_mesh.h"
#include "core/pipeline/gpc_job.h"
#include "core/pipeline/mesh2spline_job.h"
#include "core/spline/gpc_spline.h"

namespace volspline::pipeline {

/// GpcMesh2SplineOptions::hierarchy_depth's automatic values: split functions this many dyadic
/// levels below the last uniform one; where a surface map is squeezed, a tip crowded into a spot
/// of its cuboid face needs the deeper one (each level halves a cell).
constexpr int kHierarchyDepth = 3;
constexpr int kSqueezedHierarchyDepth = 6;

/// Options of the multi-cuboid mesh2spline job (the Mesh2SplineOptions fields it uses, plus the
/// GPC construction's).
struct GpcMesh2SplineOptions {
  double max_rms_rel = 0.002;      ///< stop at rms_rel ≤ this (fraction of the bbox diagonal), > 0
  /// If > 0, also refine until every surface vertex's sample is within this of the vertex
  /// (fraction of the bbox diagonal; 0 = rms only): the Hausdorff distance follows the surface
  /// error, the rms does not (an ear tip or a ring's inner side holds little of the squared
  /// misfit). Hierarchical refinement splits the functions at the samples beyond it first,
  /// adaptive refinement their knot intervals.
  double max_surface_error_rel = 0.008;
  int max_control_points = 50000;  ///< no level beyond this many control points, ≥ 64
  int max_levels = 14;             ///< knot refinements after level 0, in [0, 30]
  /// Knot intervals along the longest cuboid axis at level 0, in [1, 64]; every further level
  /// divides the knot spacing by refinement_ratio.
  int initial_cells = 4;
  double refinement_ratio = 1.5;  ///< in (1, 4]
  /// How each level refines the knots (§4.3, Algorithm 4). Uniform divides the knot spacing by
  /// refinement_ratio; Adaptive (after a uniform level 0) splits the knot intervals of the cuboid
  /// axes that hold the most misfit until the functions grow by adaptive_growth
  /// (spline::gpc_refined_knot_lines). Each cuboid stays a tensor product, so a split runs through
  /// its cross-section and every glued axis: it pays where the misfit sits in a few slabs, not for
  /// misfit spread over the solid.
  /// Hierarchical: uniform levels while rms_rel > hierarchical_from · max_rms_rel, then each
  /// level splits the functions holding the most misfit into their children one dyadic level
  /// finer (spline::gpc_marked_functions, GpcSpline::refined: a T-spline refinement that can split
  /// a cell of any cuboid, next to interfaces too), at most hierarchy_depth levels below the last
  /// uniform one.
  enum class Refinement { Uniform, Adaptive, Hierarchical } refinement = Refinement::Hierarchical;
  double adaptive_growth = 1.4;  ///< in (1, 8]; for Hierarchical the growth cap of one step
  double hierarchical_from = 2.5;  ///< ≥ 1
  double marking_fraction = 0.5;   ///< Dörfler fraction of the misfit marked per step, in (0, 1]
  /// In [1, GpcSpline::kMaxLevel], or 0: automatic, kSqueezedHierarchyDepth where a cuboid's
  /// surface map is squeezed (squeeze rounds ran, or a density stays below squeezed_below), else
  /// kHierarchyDepth.
  int hierarchy_depth = 0;
  /// Every level's least squares pulls each control point towards the previous level's spline at
  /// its anchor with this weight relative to the mean diagonal of the normal matrix
  /// (spline::GpcSplineFitOptions::regularization, ≥ 0): a function with few samples near the
  /// surface (a fine one after a split) keeps the coarser shape instead of swinging between them.
  double fit_damping = 1e-2;
  /// Least-squares weight of a surface vertex relative to a volumetric grid node (> 0).
  double surface_weight = 1.0;
  /// Surface samples: the vertices, or also every triangle's centroid at the mean of its
  /// vertices' parameters (the surface map is linear on a triangle of one cuboid face); Auto:
  /// with the centroids where a cuboid's surface map is squeezed (as for hierarchy_depth).
  enum class SurfaceSamples { Auto, Vertices, VerticesAndCentroids } surface_samples = SurfaceSamples::Auto;
  GpcOptions gpc;                 ///< the domain and its volumetric map (run_gpc)
  /// The squeeze rescue of the cuboids' surface maps (param::CuboidSurfaceMapOptions::
  /// squeezed_below), in [0, 1), 0 = off; replaces gpc.grid.squeezed_below.
  double squeezed_below = 0.1;
  /// Unfold the fitted spline with the control points inside each cuboid (spline::untangle_spline
  /// on its patch, restricted to its box); faces, surface and glued faces stay as they are.
  enum class Untangle { Off, On } untangle = Untangle::On;
  /// With untangle On, where the untangling starts: RoundsFirst runs the certificate rounds'
  /// first attempt alone from the fit (spline::SplineUntangleOptions::certificate_attempts 1) and,
  /// if that certifies every cell, skips the per-cuboid passes; otherwise the fit is restored
  /// exactly and the untangling runs as with PassesFirst (the same bytes): the per-cuboid passes,
  /// then the certificate rounds. The second fit's untangling (refit_folded_nodes) always starts
  /// with the passes: it runs only where the first left cells uncertified.
  enum class UntangleStart { RoundsFirst, PassesFirst } untangle_start = UntangleStart::RoundsFirst;
  /// With untangle On, if cells stay uncertified: fit and untangle again without the grid nodes
  /// of the hex mesh's inverted hexes (off the surface), and keep the spline with fewer
  /// uncertified cells, then the higher det_j_lower_bound_rel (stats refit_dropped_nodes).
  bool refit_folded_nodes = true;
  /// Also find the fewest functions of a uniform spline over the same GPC whose fit reaches the
  /// same rms_rel (stats uniform_control_points, uniform_rms_rel).
  enum class CompareUniform { Off, On } compare_uniform = CompareUniform::Off;
  int measure_samples = 48;       ///< per axis per surface face for hausdorff_rel, [8, 512]
  /// Cell centres per axis per cuboid at which lattice_negative_fraction is counted, [4, 256].
  int measure_lattice = 64;
  std::uint64_t seed = 1;  ///< seeds the random parameters of semi_standard_max_error
  /// Worker threads of the untangling (the cuboids run concurrently), ≥ 1 (1 creates none); the
  /// result is the same for every count.
  int threads = 1;
  /// Certificate rounds per attempt of the untangling (spline::untangle_gpc_certificate), in
  /// [0, 64]: they stop earlier once every cell is certified or the count stalls for 3 rounds, so
  /// the cap binds only where the count still falls (creased solids: about 7 s a round on a
  /// 200,000-cell spline). Fewer bound the time and may leave cells uncertified; 0 runs none.
  int certificate_rounds = 16;
};

/// "uniform", "adaptive" or "hierarchical" (stats `knot_refinement`).
const char* refinement_name(GpcMesh2SplineOptions::Refinement refinement);

/// Result of run_gpc_mesh2spline.
struct GpcMesh2SplineResult {
  spline::GpcSpline spline;  ///< over the GPC domain (sizes in bbox diagonals), points in model units
  Mesh2SplineStats stats;    ///< rms/hausdorff/jacobian/semi-standard measures and the GPC ones
};

/// A genus-0 solid's one-cuboid spline (run_mesh2spline) that folds at a Gauss point after the
/// untangling (negative_jacobian_fraction > 0: its one cube crowds thin limbs, a fork's tines) is
/// made over the GPC too, with the limbs as caps (run_gpc_mesh2spline); gpc_folds_less says
/// whether that one is kept: it folds at a smaller fraction of its Gauss points. Without the
/// untangling (options.untangle Off) the folds are asked for and the one cuboid stays.
inline bool one_cuboid_folds(const Mesh2SplineOptions& options, const Mesh2SplineStats& one) {
  return options.untangle == Mesh2SplineOptions::Untangle::On && one.negative_jacobian_fraction > 0.0;
}
inline bool gpc_folds_less(const Mesh2SplineStats& gpc, const Mesh2SplineStats& one) {
  return gpc.negative_jacobian_fraction < one.negative_jacobian_fraction;
}

/// mesh2spline over a generalized poly-cube (thesis §3.5, ch. 4): run_gpc (decomposition,
/// T-to-cube, surface and volumetric maps of every cuboid), then one cubic spline over all
/// cuboids (spline::GpcSpline: C² across regular interfaces, C⁰ at ill-points) fitted by least
/// squares to the volumetric map's hex mesh nodes (without the grid.min_quality_sweeps stage,
/// whose surface nodes leave their surface-map parameters) and the surface vertices (fit_gpc_spline),
/// its knots refined (by the misfit or uniformly, options.refinement) until rms_rel ≤
/// max_rms_rel and every surface sample is within max_surface_error_rel, then untangled and
/// measured.
/// Works on a centred copy scaled to a unit diagonal; the spline's points are in model units.
/// Throws like run_gpc, volspline::Error on bad options.
GpcMesh2SplineResult run_gpc_mesh2spline(const mesh::TriangleMesh& mesh, const std::string& name,
                                         const GpcMesh2SplineOptions& options, const Progress& progress = {});

}  // namespace volspline::pipeline
