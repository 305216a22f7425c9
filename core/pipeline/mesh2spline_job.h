// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh/triangle_mesh.h"
#include "core/param/cuboid_surface_map.h"
#include "core/common/progress.h"
#include "core/spline/jacobian_certificate.h"
#include "core/spline/tspline.h"

namespace volspline::pipeline {

/// Which samples determine the control points.
enum class Mesh2SplineFit {
  Grid,      ///< §3.4.2: volumetric grid parameterization (Eq. 3.1), then fit all samples
  Meshless,  ///< §4.3.2: boundary control points from surface samples, interior by Eq. 4.7
};

/// Options of the mesh2spline job; every field is checked on entry (volspline::Error).
struct Mesh2SplineOptions {
  double max_rms_rel = 0.002;       ///< stop when rms_rel ≤ this (fraction of bbox diagonal), > 0
  /// refine cells until every surface sample is within this of the mesh (fraction of the bbox
  /// diagonal), > 0; the Hausdorff distance is bounded by the surface error, the rms is not
  double max_surface_error_rel = 0.005;
  int max_control_points = 50000;   ///< no refinement step beyond this many control points, ≥ 64
  int max_levels = 4;               ///< refinement levels after level 0, in [0, 10]
  Mesh2SplineFit fit = Mesh2SplineFit::Grid;
  std::vector<int> corners;         ///< 8 corner vertex ids, or empty for the automatic layout
  param::SurfaceWeights weights = param::SurfaceWeights::MeanValue;
  int area_balance_iterations = 4;  ///< surface map stretch-reweighting rounds (§3.4.1 deviation), [0, 20]
  /// Squeeze rescue of the surface map after those rounds (param::CuboidSurfaceMapOptions::
  /// squeezed_below): thin tips get parameter room the spline's cells can resolve; [0, 1), 0 = off
  double squeezed_below = 0.1;
  int initial_cells = 4;            ///< spline cells along the longest cuboid axis at level 0, [1, 64]
  int grid_nodes = 0;               ///< volumetric grid nodes along the longest axis; 0 = auto; else [5, 256]
  double smoothing = 1e-4;          ///< weight of the Eq. 4.7 fairing rows (grid fit), ≥ 0
  /// After the fit, interior control points move until the scaled Jacobian is at least this at a
  /// 48³ lattice (boundary control points stay, so the surface fit is untouched); 0 = no repair
  /// (default: the repair is slow and moves the interior away from the grid samples), else in
  /// (0, 0.5]
  double min_scaled_jacobian = 0.0;
  /// Unfold the fitted spline near its folds with the interior control points (spline::
  /// untangle_spline; the boundary stays, so the surface fit is untouched). Off = the thesis's fit.
  enum class Untangle { Off, On } untangle = Untangle::On;
  /// Where the one cuboid's surface map is squeezed (the rescue ran, squeeze_rounds > 0, or a
  /// density stays below squeezed_below: a limb or tip crowded into a spot of a cube face):
  /// OneCuboid fits it all the same; Refuse throws SqueezedOneCuboid after the surface map, for
  /// the caller to take the solid through the GPC with its limbs as caps (run_gpc_mesh2spline),
  /// where each limb has cuboids of its own.
  enum class Squeezed { OneCuboid, Refuse } squeezed = Squeezed::OneCuboid;
  std::uint64_t seed = 1;           ///< seeds the random parameters of semi_standard_max_error
  /// Also fit uniform tensor B-splines to the same rms_rel (stats uniform_control_points).
  enum class CompareUniform { Off, On } compare_uniform = CompareUniform::Off;
  int measure_samples = 48;         ///< per axis per cuboid face for the surface distance, [8, 512]
};

/// The measures of DESIGN.md plus job facts (the stats JSON keys).
struct Mesh2SplineStats {
  double rms_rel = 0;              ///< RMS fitting error over the samples / bbox diagonal
  double max_rel = 0;              ///< largest fitting error / bbox diagonal
  double hausdorff_rel = 0;        ///< two-sided spline boundary ↔ mesh distance / bbox diagonal
  double rms_geo_rel = 0;          ///< RMS of the same two-sided distances / bbox diagonal
  int control_points = 0;
  int levels = 0;                  ///< refinement levels done after level 0
  /// GPC splines: per fitted level, its control points, rms_rel and the largest surface-sample
  /// misfit over the bbox diagonal (the convergence curve).
  struct Level {
    int control_points = 0;
    double rms_rel = 0.0;
    double surface_max_rel = 0.0;
  };
  std::vector<Level> level_history;
  /// From the Bernstein certificate of det J (spline::certify_jacobian): the fraction of
  /// knot-line cells with det J ≥ 0 proven, the smallest certified bound scaled like the scaled
  /// Jacobian (negative if a cell is not certified), and every cell that is not certified.
  double jacobian_certified_fraction = 0;
  double det_j_lower_bound_rel = 0;
  std::vector<spline::UncertifiedCell> uncertified_cells;
  int certificate_cells = 0;       ///< knot-line cells certified or not
  double min_scaled_jacobian = 0;  ///< at the 3×3×3 Gauss points of every knot-line cell
  double negative_jacobian_fraction = 0;  ///< fraction of those points with scaled Jacobian ≤ 0
  long jacobian_samples = 0;       ///< number of those points
  double semi_standard_max_error = 0;  ///< max |Σ w_i B_i − 1| at 10⁵ random parameters
  int cuboids = 1;
  // GPC splines (run_gpc_mesh2spline); one cuboid: genus 0, no interfaces.
  int genus = 0;
  int t_shapes = 0;
  int ill_points = 0;
  int interfaces = 0;                  ///< glued face pairs
  int continued_interfaces = 0;        ///< of those, C² (regular); the others are C⁰ (ill-points)
  double interface_gap_rel = 0;        ///< largest |F_a − F_b| at dense samples of glued faces / diagonal
  double interface_normal_jump_deg = 0;  ///< largest angle between the two sides' ∂F/∂n, regular interfaces
  /// Fraction of the measure_lattice³ cell centres of every cuboid with scaled Jacobian ≤ 0.
  double lattice_negative_fraction = 0;
  long lattice_samples = 0;
  int flipped_triangles = 0;           ///< of the surface map (0: bijective)
  /// Squeeze rescue rounds of the surface map (most over the cuboids' maps; squeezed_below).
  int squeeze_rounds = 0;
  /// Least linear parameter density of a surface vertex inside a cube face, over all maps: below
  /// squeezed_below where the rescue could not open a squeeze.
  double surface_least_density = 0;
  /// GPC splines: the hierarchy depth used (GpcMesh2SplineOptions::hierarchy_depth, resolved)
  /// and whether the triangles' centroids were fitted (surface_samples, resolved).
  int hierarchy_depth = 0;
  bool centroid_samples = false;
  /// GPC splines: grid nodes of inverted hexes left out of the second fit (refit_folded_nodes),
  /// 0 if the first fit was kept or no second fit ran.
  int refit_dropped_nodes = 0;
  int grid_inverted_hexes = 0;         ///< of the volumetric grid map (grid fit)
  double grid_min_scaled_jacobian = 1; ///< of the volumetric grid map (grid fit)
  /// GPC splines: the GPC job's retried constructions that ran (GpcStats::retries), by its stat's
  /// name, each saying what was tried and kept.
  std::map<std::string, std::string> domain_retries;
  /// of the fit before the untangling and the repair, at the points the untangler (24³ cell
  /// centres) or the repair scans; without either, negative_jacobian_fraction
  double negative_jacobian_fraction_fit = 0;
  int repaired_control_points = 0;            ///< interior control points the repair moved
  int untangled_control_points = 0;           ///< interior control points free in the untangling
  /// GPC splines: the farthest the untangling moved the spline at a surface sample's parameter,
  /// over the bbox diagonal (0 without untangling): the surface accuracy the unfolding cost,
  /// which hausdorff_rel includes.
  double untangle_surface_shift_rel = 0;
  /// GPC splines: the kept untangling's path, "rounds" (the certificate rounds' first attempt
  /// alone certified every cell, GpcMesh2SplineOptions::untangle_start RoundsFirst) or "passes"
  /// (the per-cuboid passes, then the rounds' attempts); empty without untangling.
  std::string untangle_path;
  /// GPC splines: the kept untangling's certificate passes, all attempts (SplineUntangleResult::
  /// certificate_passes), and the local ones among them (SplineUntangleResult::local_passes).
  int certificate_passes = 0;
  int local_certificate_passes = 0;
  /// bd-control-points the untangler's crease tilt moved (spline::convex_edge_creases; 0 if none)
  int creased_control_points = 0;
  int samples = 0;
  double min_corner_distance_rel = 0;  ///< closest cuboid corner pair / bbox diagonal
  std::array<int, 8> corners{};        ///< corner vertex ids used
  /// Uniform tensor B-spline fitted to the same samples with rms_rel ≤ the T-spline's
  /// (compare_uniform): its control points (−1: not computed or not reached) and rms_rel.
  int uniform_control_points = -1;
  double uniform_rms_rel = 0;
  std::vector<std::pair<std::string, double>> times_s;  ///< per stage, seconds, in run order
};

/// Puts a det J certificate (DESIGN §6) into the stats: jacobian_certified_fraction,
/// det_j_lower_bound_rel, certificate_cells, uncertified_cells (moved out of `certificate`).
void record_certificate(Mesh2SplineStats& stats, spline::JacobianCertificate certificate);

/// Thrown by run_mesh2spline (options.squeezed Refuse) when the one cuboid's surface map is
/// squeezed: the input is fine, one cuboid is the wrong domain for it.
class SqueezedOneCuboid : public std::runtime_error {
 public:
  SqueezedOneCuboid(const std::string& message, int squeeze_rounds)
      : std::runtime_error(message), squeeze_rounds(squeeze_rounds) {}
  int squeeze_rounds;  ///< of the one cuboid's surface map
};

/// Result of the mesh2spline job.
struct Mesh2SplineResult {
  spline::TSpline spline;  ///< domain [0,1]³, semi-standard, geometry (D = 3)
  Mesh2SplineStats stats;
};

/// Closed genus-0 triangle mesh → one cuboid → trivariate T-spline (thesis ch. 3, 4):
/// validate, cuboid layout, surface map (§3.4.1), volumetric grid (§3.4.2, grid fit; its folds
/// untangled), boundary restricted control grid (§4.3.1), least-squares fit with hierarchical
/// refinement (spline::run_hierarchical_fitting), untangling of the spline's folds (options.untangle),
/// measures. `name` is used in error messages.
/// Throws volspline::Error on bad options or input: open, non-manifold, several components,
/// genus ≠ 0, inconsistent orientation, degenerate faces, NaN, or no valid cuboid map;
/// volspline::Cancelled if progress asks to stop.
Mesh2SplineResult run_mesh2spline(const mesh::TriangleMesh& mesh, const std::string& name,
                                  const Mesh2SplineOptions& options, const Progress& progress = {});

}  // namespace volspline::pipeline
