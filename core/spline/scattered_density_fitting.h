// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/common/progress.h"
#include "core/spline/density_fitting.h"
#include "core/spline/hierarchical_refinement.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Outcome of fit_tspline_scattered.
struct ScatteredFitResult {
  int unknowns = 0;
  int cg_iterations = 0;
  bool converged = false;
  long long normal_nonzeros = 0;
};

/// Least-squares fit (Eq. 3.5/3.6) of columns components[k] of the control points of `spline`
/// to targets.col(k) at scattered parameters uvw (m×3, inside the domain). The samples are
/// grouped by their exact list of non-zero blending functions (one knot-grid cell of the
/// T-spline has one list), so each group adds one dense Gram block (the lower triangle of MᵀM by
/// a symmetric rank update) to the upper triangle of the sparse normal matrix. Solved with CG +
/// SparsifiedCholesky, warm-started from the current control points, with a ridge of
/// `regularization` × each diagonal entry (the mean one for an empty row) towards them.
/// A spline with cell polynomials is rebuilt with TSplineAcceleration::FunctionLists.
/// Preconditions: targets has m rows and components.size() columns; uvw inside the domain.
ScatteredFitResult fit_tspline_scattered(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixXd& targets,
                                         const std::vector<int>& components, const GridFitOptions& options = {});

/// Result of fit_scattered_adaptive.
struct ScatteredDensityResult {
  TSpline spline;                            ///< D = 4: (X, Y, Z, density) over [0, 1]³ (Eq. 5.11)
  std::vector<AdaptiveDensityLevel> levels;  ///< density error per level, level 0 first
  std::vector<double> reconstruction;        ///< F_density at every sample
  FitStopReason stop_reason = FitStopReason::Target;
};

/// Adaptive hierarchical fit (run_hierarchical_fitting) of (X, Y, Z, density) samples at parameters uvw
/// (m×3 inside [0, 1]³; targets m×4) as fit_density_adaptive does on a grid: level 0 is the
/// uniform cubic B-spline on initial cells (proportional to dims), then Dörfler-marked leaves
/// are split by RefinementGrid::split and the density refitted; X, Y, Z are fitted once at the
/// end, with the last level's factorized normal matrix. Density errors are relative to the
/// range of targets.col(3); min_cell_width is in voxels (1/(dims−1) in uvw). Throws
/// volspline::Error on bad options, shape mismatches or parameters outside [0, 1]³; Cancelled
/// if progress asks to stop.
ScatteredDensityResult fit_scattered_adaptive(const Eigen::MatrixX3d& uvw, const Eigen::MatrixXd& targets,
                                              const std::array<int, 3>& dims,
                                              const AdaptiveDensityOptions& options = {},
                                              const Progress& progress = {});

}  // namespace volspline::spline
