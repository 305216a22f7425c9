// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/polycube/cube_faces.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Options of the least-squares fits.
struct TSplineFitOptions {
  /// Weight of the Eq. 4.7 Laplacian rows relative to the sample rows (unitless ≥ 0): a small
  /// fairing term that keeps control points without samples well defined.
  double smoothing = 1e-4;
  /// Tikhonov weight pulling each control point towards its prior, relative to the mean
  /// diagonal of the normal matrix (unitless > 0): keeps the system SPD when blending
  /// functions are linearly dependent or unsampled.
  double regularization = 1e-3;
  /// Nodes per axis of the uniform parameter grid carrying the Eq. 4.7 rows; 0 = automatic
  /// (twice the number of knot intervals plus one, between 9 and 65).
  int laplacian_nodes = 0;
  double tolerance = 1e-10;  ///< relative CG residual
  int max_iterations = 4000; ///< CG iteration cap per solve
  /// Faces of the domain box on the solid's surface: the meshless fit takes the control points of
  /// the functions touching them from the surface samples (Eq. 4.4/4.5).
  polycube::CubeFaceSet exposed_faces = polycube::CubeFaceSet::all();
};

/// Outcome of a fit.
struct TSplineFitResult {
  int cg_iterations = 0;
  bool converged = false;
  int rows = 0;     ///< rows of the stacked least-squares system
  int unknowns = 0; ///< control points solved for
};

/// Least-squares fit of all control points (Eq. 3.5/3.6): minimizes
/// Σ_i ‖F(uvw_i) − xyz_i‖² + smoothing·Σ_g ‖Σ_j w_gj F(u_j)‖² (Eq. 4.7 on a uniform grid)
/// + regularization·‖p − prior‖², solving the normal equations with CG + IC(0), warm-started
/// from the current control points. uvw: m×3 parameters inside the domain; xyz: m×3 targets;
/// prior: n×3 (n = num_functions()). Replaces the spline's control points.
/// Precondition: the spline has dimension 3.
TSplineFitResult fit_tspline(TSpline& spline, const Eigen::MatrixX3d& uvw,
                             const Eigen::MatrixX3d& xyz, const Eigen::MatrixX3d& prior,
                             const TSplineFitOptions& options = {});

/// fit_tspline restricted to the control points of `free_functions` (indices into the spline,
/// increasing, no repeats), the others fixed: the rows are the samples and Eq. 4.7 nodes on
/// which some free blending function is non-zero, the fixed part moves to the right-hand side.
/// After a local refinement the refined spline equals the previous fit, so re-fitting only the
/// functions near the split cells is a block step of the same least-squares problem (the rest
/// already fits). Same inputs and preconditions as fit_tspline; asserts the indices are valid.
TSplineFitResult fit_tspline_local(TSpline& spline, const Eigen::MatrixX3d& uvw,
                                   const Eigen::MatrixX3d& xyz, const Eigen::MatrixX3d& prior,
                                   const std::vector<int>& free_functions,
                                   const TSplineFitOptions& options = {});

/// True iff blending function `knots` is non-zero somewhere on one of the `exposed` faces of the
/// patch's domain box [lo, hi] (a "bd-control-point" of §4.3.1): along axis a, 4 equal knots
/// r0 = r3 = lo_a for face 2a or r1 = r4 = hi_a for face 2a + 1 (polycube::cube_faces.h). All six
/// exposed: a single-cuboid solid; a face glued to another cuboid is not exposed.
bool touches_exposed_face(const BlendingKnots& knots, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                          polycube::CubeFaceSet exposed);

/// Meshless fit (§4.3.2): first the control points of the blending functions that touch the
/// domain boundary from surface samples only (Eq. 4.4/4.5), then the interior control points
/// minimizing the discrete Laplacian of F on a uniform parameter grid (Eq. 4.6/4.7) with the
/// boundary ones fixed. uvw: m×3 parameters on the boundary of the domain; xyz: m×3 surface
/// points; prior as in fit_tspline. Replaces the spline's control points.
TSplineFitResult fit_tspline_meshless(TSpline& spline, const Eigen::MatrixX3d& uvw,
                                      const Eigen::MatrixX3d& xyz, const Eigen::MatrixX3d& prior,
                                      const TSplineFitOptions& options = {});

}  // namespace volspline::spline
