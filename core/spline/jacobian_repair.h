// SPDX-License-Identifier: MIT
#pragma once

#include "core/polycube/cube_faces.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Options of repair_jacobian.
struct JacobianRepairOptions {
  /// The points checked are the interior nodes j/lattice (j = 1 .. lattice−1) per axis of the
  /// domain, in [4, 256]; 48 contains the cell centres of a 24³ lattice.
  int lattice = 48;
  /// Scaled Jacobian det J / (|J e0| |J e1| |J e2|) asked for at every point, in (0, 1).
  double min_scaled_jacobian = 0.05;
  int max_iterations = 20;  ///< Gauss–Newton steps, ≥ 0
  /// Faces of the domain box on the solid's surface: the control points of the functions
  /// touching them stay fixed (a glued face's functions may move).
  polycube::CubeFaceSet exposed_faces = polycube::CubeFaceSet::all();
};

/// Outcome of repair_jacobian.
struct JacobianRepairResult {
  int points = 0;             ///< lattice points checked
  int initial_negative = 0;   ///< points with det J ≤ 0 before
  int final_negative = 0;     ///< and after
  double initial_min_scaled = 1.0;
  double final_min_scaled = 1.0;
  int iterations = 0;
  int moved_points = 0;       ///< interior control points that moved
};

/// Makes a geometric T-spline (D = 3) foldover-free at a lattice of parameter points by moving
/// only INTERIOR control points (blending functions that vanish on the domain boundary, §4.3.1),
/// so the boundary surface, and the surface fit, are untouched.
///
/// Minimizes Σ_s (max(0, τ·σ_s − det J_s) / σ_s)² over the points s (τ = min_scaled_jacobian,
/// σ_s = |j0||j1||j2| of the input spline, fixed, so the penalty is a polynomial in the control
/// points) by damped Gauss–Newton: det J is linear in each control point, ∂ det J / ∂p_i =
/// w_i cof(J) ∇B_i; the normal equations of the violated points are solved by CG, a step is
/// kept only if the penalty drops (else halved, at most 4 times).
/// Points where no interior control point acts (det J fixed by the boundary alone) cannot
/// change and stay as they are. Precondition: dimension() == 3.
JacobianRepairResult repair_jacobian(TSpline& spline, const JacobianRepairOptions& options = {});

}  // namespace volspline::spline
