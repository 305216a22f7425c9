// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/common/progress.h"
#include "core/spline/density_fitting.h"
#include "core/spline/tspline.h"
#include "core/volume/frame_field.h"
#include "core/volume/volume.h"

namespace volspline::pipeline {

/// Parameterization the spline is fitted over.
enum class Vol2SplineParam {
  Identity,  ///< the plain voxel grid (no frame field): the honest baseline of the issue
  Aligned,   ///< frame-field-aligned parameterization (§5.3, Eq. 5.7/5.10)
};

/// Options of the vol2spline job; every field is checked on entry (volspline::Error).
struct Vol2SplineOptions {
  double max_rms_rel = 0.005;       ///< stop refining at density RMS / density range ≤ this, > 0
  int max_control_points = 0;       ///< the spline never has more control points, ≥ 64; 0 = automatic (voxels/16 within [64, 50000], spline::automatic_control_point_budget)
  int max_levels = 10;              ///< refinement levels after level 0, in [0, 20]
  double min_gain_rate = 0.25;      ///< stop after a level with ln(rms ratio)/ln(control point ratio) below this, ≥ 0 (0 = off); spline::AdaptiveDensityOptions
  int initial_cells = 0;            ///< level-0 cells along the longest axis; 0 = automatic (longest/8)
  Vol2SplineParam param = Vol2SplineParam::Identity;
  enum class ComputeFrames { Off, On } compute_frames = ComputeFrames::Off;  ///< identity: also run the frame stages (aligned always does)
  int clusters = 0;                 ///< k-means clusters, 0 = automatic, else [2, 16]
  double iso = std::numeric_limits<double>::quiet_NaN();  ///< if finite: threshold classification at this sample value
  std::vector<std::size_t> corners; ///< corner voxel ids (flat x + nx(y + ny z)); empty = automatic
  int threads = 1;                  ///< worker threads in [1, 256] (1 creates none); the output is the same for every count
};

/// The measures of DESIGN.md for volumes plus job facts (the stats JSON keys).
struct Vol2SplineStats {
  double density_rms_rel = 0;      ///< RMS of (F_density − sample) over all voxels / density range
  double density_max_rel = 0;      ///< max |F_density − sample| / density range
  int control_points = 0;
  std::size_t voxels = 0;
  int patches = 1;                 ///< one patch: the parameterization covers the whole box
  int corners = 0;                 ///< corner constraints used by the aligned parameterization
  int levels = 0;                  ///< refinement levels done after level 0
  int max_control_points = 0;      ///< the budget the fit ran with (after resolving 0 = automatic)
  std::string stop_reason;         ///< why refinement stopped: spline::fit_stop_reason_name
  int clusters = 0;                ///< materials found (frame stages only)
  int constraints = 0;             ///< constrained boundary voxels (frame stages only)
  bool frames_computed = false;    ///< the frame fields below are meaningful
  double frame_smoothness_initial = 0;  ///< Eq. 5.6 before smoothing
  double frame_smoothness_final = 0;    ///< Eq. 5.6 after smoothing
  int frame_iterations = 0;
  double constraint_angle_max_deg = 0;  ///< largest angle between a constraint normal and its frame axis
  double min_scaled_jacobian = 1;  ///< of the spline geometry (X, Y, Z) at the cell centres of a 16³ lattice
  double param_min_jacobian = 1;   ///< of the voxel map (aligned) or 1 (identity)
  int param_inverted_cells = 0;
  std::vector<spline::AdaptiveDensityLevel> curve;  ///< control points vs density RMS, per level
  std::vector<std::pair<std::string, double>> times_s;  ///< per stage, seconds, in run order
};

/// Result of the vol2spline job.
struct Vol2SplineResult {
  /// Semi-standard T-spline F(u, v, w) = (X, Y, Z, density) (Eq. 5.11, D = 4); X, Y, Z in the
  /// volume's world (Volume::voxel_position: origin + direction · (voxel index × spacing)). Domain: [0, n_a − 1] (identity) or [0, 1]³ (aligned).
  spline::TSpline spline;
  Vol2SplineStats stats;
  std::vector<double> reconstruction;  ///< F_density at every voxel (x fastest)
  volume::FrameField frames;           ///< smoothed frames (empty unless the frame stages ran)
  Eigen::MatrixX3d uvw;                ///< per-voxel parameters (aligned), else empty
};

/// Voxel volume → frame field → parameterization → T-spline of (X, Y, Z, density) (thesis ch. 5):
/// local cubic fits (Eq. 5.1–5.4), Hessian frames (Eq. 5.5), material classification and
/// frame constraints, frame smoothing (§5.2.2, Eq. 5.6), corners and field-aligned
/// parameterization (§5.3), adaptive T-spline fit (Eq. 5.11, spline::run_hierarchical_fitting). With
/// Vol2SplineParam::Identity and compute_frames off, only the fit runs. `name` is used in messages.
/// The stages run on a copy with the spacing divided by its largest component, without origin and
/// direction, and the spline is mapped back: the same volume in other units or at another place
/// gives the same control points and measures.
/// Throws volspline::Error on bad options, a volume with a dimension < 2 (< 5 with frames), a
/// spacing that is not positive and finite or whose components are more than 1e12 apart, or a
/// non-finite origin or direction; volspline::Cancelled if progress asks to stop.
Vol2SplineResult run_vol2spline(const volume::Volume& volume, const std::string& name,
                                const Vol2SplineOptions& options, const Progress& progress = {});

}  // namespace volspline::pipeline
