// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/common/progress.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/hierarchical_fitting.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Scalar samples on a regular grid, x fastest: sample (x, y, z) is values[x + nx·(y + ny·z)] and
/// sits at parameter (x, y, z) (voxel index units), so the grid spans [0, nx−1]×[0, ny−1]×[0, nz−1].
struct GridSamples {
  std::array<int, 3> dims{0, 0, 0};
  std::vector<double> values;
};

/// Density error of a reconstruction, relative to the sample range max − min (1 if the range is 0).
struct GridError {
  double rms_rel = 0.0;  ///< sqrt(mean (F − v)²) / range
  double max_rel = 0.0;  ///< max |F − v| / range
};

/// Error of `reconstruction` (same layout as samples.values) against the samples.
/// Precondition: sizes agree.
GridError grid_error(const GridSamples& samples, const std::vector<double>& reconstruction);

/// Result of fit_uniform_bspline.
struct UniformBsplineFit {
  BsplineVolume volume;               ///< dimension 1, clamped uniform knots on [0, n_a − 1]
  std::vector<double> reconstruction; ///< F at every sample, layout of GridSamples::values
  GridError error;
};

/// Least-squares cubic tensor-product B-spline with control_points[a] (≥ 4) uniform clamped basis
/// functions per axis over the sample grid: the baseline of the vol2spline issue. The sample set is
/// a full tensor grid, so the least-squares operator factors into three 1D ones (B_z⁺ ⊗ B_y⁺ ⊗ B_x⁺)
/// applied axis by axis: exact, no iteration. Throws volspline::Error if a dimension is < 2 or
/// has fewer samples than basis functions, or control_points[a] < 4.
UniformBsplineFit fit_uniform_bspline(const GridSamples& samples, const std::array<int, 3>& control_points);

/// Options of fit_tspline_to_grid.
struct GridFitOptions {
  double tolerance = 1e-5;      ///< relative CG residual of the normal equations (1e-5 moves the density RMS by < 1e-6 relative on the shared volumes)
  int max_iterations = 3000;    ///< CG iteration cap per solve
  double regularization = 1e-3; ///< ridge towards the current control points, relative to each diagonal entry (> 0)
  int threads = 1;              ///< worker threads (≥ 1; 1 creates none); the result is the same for every count
};

/// Outcome of fit_tspline_to_grid.
struct GridFitResult {
  int unknowns = 0;
  int cg_iterations = 0;
  bool converged = false;
  long long normal_nonzeros = 0;
};

/// Least-squares fit of the control points of `spline` (Eq. 3.5/3.6, semi-standard form
/// F = Σ w_i p_i B_i) to grid samples: for each k, column components[k] of the control points
/// is fitted to targets[k] (one value per sample, layout of GridSamples::values). Because the
/// samples form a tensor grid with unit weights, each normal-matrix entry Σ_s B_i B_j is the
/// product of three 1D sums, so the sparse normal matrix is assembled without touching the
/// samples; the right-hand sides cost one pass over every support. Solved with CG + SparsifiedCholesky,
/// warm-started from the current control points. Parameters outside the spline's domain are
/// not sampled. A spline with cell polynomials is rebuilt with TSplineAcceleration::FunctionLists.
/// Precondition: the domain contains [0, n_a − 1]; targets sizes match dims.
GridFitResult fit_tspline_to_grid(TSpline& spline, const std::array<int, 3>& dims,
                                  const std::vector<int>& components,
                                  const std::vector<const std::vector<double>*>& targets,
                                  const GridFitOptions& options = {});

/// Component `component` of F (semi-standard form) at every grid sample (x fastest), by
/// accumulating each blending function over its support. Precondition: the domain contains the grid.
std::vector<double> evaluate_on_grid(const TSpline& spline, int component, const std::array<int, 3>& dims);

/// Control points an adaptive density fit may use when its options leave the budget automatic:
/// one per 16 samples, within [64, 50000]. A spline with more coefficients than that is no longer
/// a compact smooth model of the samples, and on noisy volumes (neghip) the RMS target is then
/// out of reach anyway.
int automatic_control_point_budget(std::size_t num_samples);

/// Options of fit_density_adaptive.
struct AdaptiveDensityOptions {
  double max_rms_rel = 0.005;      ///< stop when the density RMS / range is at most this (> 0)
  int max_control_points = 0;      ///< the result never has more control points (≥ 64); 0 = automatic_control_point_budget
  int initial_cells = 0;           ///< level-0 cells per axis, rounded down to a power of 2 (≤ 256); 0 = automatic (longest/8)
  double min_cell_width = 0.5;     ///< voxels; cells narrower than 2× this are not split (> 0)
  double marking_fraction = 0.5;   ///< Dörfler fraction of the squared error whose cells are split (0, 1]
  int max_levels = 10;             ///< refinement levels after level 0 (≥ 0)
  double min_decrease_rel = 0.02;  ///< stop after a level that lowered the RMS by less than this fraction, [0, 1)
  /// Stop after a level whose gain per added control point, ln(rms_before / rms) / ln(n / n_before)
  /// (the slope of the log-log curve; a cubic fit of smooth data reaches 4/3), is below this (≥ 0;
  /// 0 = off).
  double min_gain_rate = 0.25;
  /// A level is only started if the budget leaves room for at least this fraction more control
  /// points, [0, 1): a nearly full budget would buy a full refit for a few points.
  double min_level_growth = 0.25;
  GridFitOptions fit;
};

/// One level of adaptive fitting.
struct AdaptiveDensityLevel {
  int control_points = 0;
  double rms_rel = 0.0;
  double max_rel = 0.0;
  int cg_iterations = 0;
  int leaves = 0;
};

/// Result of fit_density_adaptive.
struct AdaptiveDensityResult {
  /// Dimension-4 spline F(u, v, w) = (X, Y, Z, density) with X, Y, Z the sample grid position in
  /// voxel index units (an exact linear fit: the identity parameterization of Eq. 5.11).
  TSpline spline;
  std::vector<AdaptiveDensityLevel> levels;  ///< level 0 first; the last one is `spline`
  std::vector<double> reconstruction;        ///< density at every sample
  GridError error;
  int max_level = 0;
  FitStopReason stop_reason = FitStopReason::Target;
};

/// True if the last of `levels` (level 0 first) gained too little over the one before: its RMS
/// fell by less than min_decrease_rel, or ln(rms_before / rms) / ln(n / n_before) < min_gain_rate.
bool level_gain_too_small(const std::vector<AdaptiveDensityLevel>& levels, const AdaptiveDensityOptions& options);

/// Why an adaptive fit with `count` control points and RMS `rms_rel` stops instead of refining
/// `level` (≥ 1): Target, Diminishing (level_gain_too_small), MaxLevels, or Budget (a level only
/// starts while the budget leaves min_level_growth · count room); nothing if it goes on.
std::optional<FitStopReason> adaptive_stop(double rms_rel, const std::vector<AdaptiveDensityLevel>& levels, int level,
                                           int count, int budget, const AdaptiveDensityOptions& options);

/// Adaptive hierarchical T-spline fit of grid samples (run_hierarchical_fitting): level 0 is the
/// least-squares cubic B-spline on 2^k uniform cells per axis; then the leaves holding the largest share of
/// the squared error (Dörfler marking) are split into 8 by RefinementGrid::split and all control
/// points refitted, until the RMS target, the control point budget (a level that would exceed it
/// is shrunk or discarded), diminishing returns (min_gain_rate, min_decrease_rel) or max_levels;
/// the result says which. Throws volspline::Error on bad options or fewer than 2 samples
/// along an axis; Cancelled if progress asks to stop.
AdaptiveDensityResult fit_density_adaptive(const GridSamples& samples,
                                           const AdaptiveDensityOptions& options = {},
                                           const Progress& progress = {});

}  // namespace volspline::spline
