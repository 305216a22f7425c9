// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/spline/gpc_spline.h"

namespace volspline::spline {

/// Samples of a map over a GPC: sample s lies in cuboid cuboid[s] at local coordinates
/// uvw.row(s) (inside that cuboid's box) and has the target value values.row(s).
struct GpcSamples {
  std::vector<int> cuboid;  ///< m cuboid ids
  Eigen::MatrixX3d uvw;     ///< m×3 local coordinates (units of the cuboid sizes)
  Eigen::MatrixXd values;   ///< m×D targets (xyz in model units for geometry)
  /// m least-squares weights (each finite and > 0), or empty for all 1.
  std::vector<double> weight;
};

/// Options of fit_gpc_spline.
struct GpcSplineFitOptions {
  /// Tikhonov weight pulling every control point towards its current position, relative to the
  /// mean diagonal of the normal matrix (unitless, ≥ 0): keeps the system SPD where functions are
  /// sampled too sparsely. 0 gives the plain least-squares solution when it is unique.
  double regularization = 1e-8;
  double tolerance = 1e-12;    ///< relative CG residual (unitless, ≥ 0)
  int max_iterations = 10000;  ///< CG iteration cap, ≥ 1
};

/// Outcome of fit_gpc_spline.
struct GpcSplineFitReport {
  bool converged = false;         ///< CG reached the tolerance
  int cg_iterations = 0;
  double cg_residual = 0.0;       ///< relative residual reached
  int samples = 0;
  int unknowns = 0;               ///< control points solved for
  int unsampled_functions = 0;    ///< functions non-zero at no sample: kept where they were
  double rms_error = 0.0;         ///< RMS of ‖F(uvw_s) − values_s‖ after the fit, units of values
  double max_error = 0.0;         ///< largest ‖F(uvw_s) − values_s‖ after the fit
};

/// Least-squares fit of all global control points to samples over every cuboid at once
/// (Eq. 3.5/3.6 over the GPC of §3.5): minimizes Σ_s weight_s ‖F_{c_s}(uvw_s) − values_s‖²
/// + ε²‖p − p_current‖² (ε² = regularization · mean diagonal) by CG with IC(0) on the normal
/// equations, warm-started from the current control points, then replaces them. Samples of one
/// knot cell of one cuboid share their blending functions and are added as one dense Gram block.
/// A function no sample reaches keeps its control point. Non-convergence is reported, not thrown.
/// The reported errors are unweighted.
/// Throws volspline::Error if the shapes disagree (m entries in cuboid, m×3 uvw, m×D values with
/// D = spline.dimension(), 0 or m weights), a weight is not finite and positive, a cuboid id is out of range, a uvw is outside its cuboid or not
/// finite, a value is not finite, or an option is out of range.
GpcSplineFitReport fit_gpc_spline(GpcSpline& spline, const GpcSamples& samples,
                                  const GpcSplineFitOptions& options = {});

/// Knot lines of an error-driven refinement of `spline` (Algorithm 4's marking, §4.3, on the knot
/// intervals of every cuboid axis). A GPC-spline stays a tensor product per cuboid with the knot
/// lines shared through the gluing, so the refinable unit is a knot interval of one axis, not a
/// cell: each sample's weighted squared misfit weight_s ‖F(uvw_s) − values_s‖² is shared among
/// the intervals holding it along the three axes in proportion to (h_a³ ‖∂³F/∂u_a³‖)² there (the
/// axes along which F is far from quadratic at this knot spacing); intervals are split at their
/// midpoint in decreasing order of what they received
/// (gpc_insert_knot_line: through every glued axis) until the estimated number of functions,
/// Σ_c Π_a (intervals + 3), has grown by `growth` (> 1) or no interval with misfit is left. No
/// half gets shorter than min_interval[c][a] (cuboid units; empty: no limit), e.g. the sample
/// spacing, so that every function keeps samples. The samples listed in `first` (ids, most
/// important first, e.g. surface samples beyond a tolerance) have the interval holding them along
/// their axis of largest share split before any other. Deterministic (ties by cuboid, axis,
/// interval).
/// Throws volspline::Error like fit_gpc_spline on malformed samples, if growth is not > 1,
/// min_interval does not hold one triple per cuboid or an id in `first` is out of range.
std::vector<std::array<std::vector<double>, 3>> gpc_refined_knot_lines(
    const GpcSpline& spline, const GpcSamples& samples, double growth,
    const std::vector<std::array<double, 3>>& min_interval = {}, const std::vector<int>& first = {});

/// Functions to split in one hierarchical step (Algorithm 4's marking over the GPC, §4.3.3, for
/// GpcSpline::refined): each sample's weighted squared misfit weight_s ‖F(uvw_s) − values_s‖² is
/// shared among the functions non-zero there in proportion to w_i B_i(uvw_s) (they sum to 1,
/// Eq. 4.3); functions are taken in decreasing order of their share until they hold `fraction`
/// (in (0, 1]) of the total (Dörfler marking) or max_count (≥ 1) are taken. Functions at level
/// ≥ max_level are never taken. `first`: sample ids (such as surface vertices beyond a distance
/// bound) whose functions are taken before the marking: at each, in the given order, every function
/// with w_i B_i at least half the largest there (a misfit the squared sum hides, at a thin
/// feature). Increasing ids; deterministic (ties by id).
/// Throws volspline::Error like fit_gpc_spline on malformed samples or if an argument is out of range.
std::vector<int> gpc_marked_functions(const GpcSpline& spline, const GpcSamples& samples, double fraction,
                                      int max_count, int max_level, const std::vector<int>& first = {});

}  // namespace volspline::spline
