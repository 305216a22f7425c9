// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "core/spline/tspline.h"

namespace volspline::spline {

/// Options of untangle_spline.
struct SplineUntangleOptions {
  /// Check points: the nodes j/lattice, j = 1 .. lattice−1, per axis of the domain, in [4, 256];
  /// 48 holds the cell centres of a 24³ lattice (the odd j), where the measures look.
  int lattice = 48;
  /// Points whose scaled Jacobian is below this seed the untangling, in [0, 1).
  double min_scaled_jacobian = 0.02;
  /// Only every seed_stride-th lattice node per axis (from the first odd one) is scanned for
  /// seeds, in [1, 4]; 2 scans the 24³ cell centres of the 48 lattice. The energy then covers
  /// every energy node near a seed.
  int seed_stride = 2;
  /// The energy holds every energy_stride-th lattice node per axis (from the first), ≥ 1 and a
  /// divisor of seed_stride (so it holds the scanned nodes). 2: the 24³ cell centres, 8× fewer
  /// terms than 1 (bunny's stage ~5× faster); nodes between them are not held, so a finer check
  /// sees folds (of 64³ points, folded after: bunny 1,169 against 1,390 with 1, bimba 666
  /// against 459). The measures look at 64³ cell centres, none of which is a lattice node.
  int energy_stride = 2;
  int rings = 1;               ///< lattice steps around a seed whose interior functions move, [0, 4]
  /// Only interior functions whose support spans at most this many lattice steps per axis move
  /// (the energy covers their whole supports, so coarse functions would make it global), ≥ 4;
  /// doubled for a seed where such functions carry under a tenth of |w∇B| (they could not
  /// unfold it), and in each further pass.
  double max_support_steps = 16;
  int passes = 3;              ///< scan + untangle rounds while seeds remain, ≥ 1
  double data_weight = 10.0;   ///< weight of the sample term (unitless ≥ 0), see untangle_spline
  double volume_weight = 0.5;  ///< θ of param::foldover_free_energy, in [0, 1)
  int max_steps = 12;          ///< ε-continuation steps, ≥ 1
  int max_inner = 5;           ///< L-BFGS iterations per step, ≥ 1
};

/// Outcome of untangle_spline.
struct SplineUntangleReport {
  int scanned = 0;            ///< lattice points scanned for seeds (and checked after)
  int seeds = 0;              ///< scanned points below min_scaled_jacobian before
  int initial_negative = 0;   ///< scanned points with det J ≤ 0 before
  int final_negative = 0;     ///< and after
  double final_min_scaled = 1.0;  ///< over the scanned points, after
  int free_functions = 0;     ///< interior control points that were free to move
  int points = 0;             ///< energy nodes
  int samples = 0;            ///< samples in the data term
  int iterations = 0;         ///< L-BFGS iterations
};

/// Unfolds a geometric T-spline (D = 3) near its folds by moving only interior control points
/// (blending functions that vanish on the domain boundary, §4.3.1), so the boundary surface
/// and the surface fit stay exactly as they are.
///
/// Seeds: scanned lattice points with scaled Jacobian < min_scaled_jacobian. Free: the interior
/// functions non-zero within `rings` lattice steps of a seed (support limit: max_support_steps).
/// Energy: Σ over the energy nodes (every energy_stride-th lattice node) in the support of a free
/// function of param::foldover_free_energy(J·S⁻¹), S = the point's initial J where its scaled
/// Jacobian is ≥ 0.1, else diag of its column norms |∂F/∂u_a| (the map's own local shape is the
/// reference), plus
/// data_weight·Σ_s ‖F(uvw_s) − xyz_s‖²/ℓ² over the samples where a free function is non-zero
/// (ℓ: one lattice step in model units), so the interior stays near its samples. Minimized by
/// param::untangle (L-BFGS with the barrier continuation of Garanzha et al. 2021), until every
/// scanned point and every energy node not folded before has det J > 0. J at the energy
/// nodes is a fixed linear map of the free control points (the knots do not move), so it is
/// set up once per pass and each energy evaluation sums tensor products of univariate factors.
/// uvw, xyz: m×3 fitting samples (may be empty). Precondition: dimension() == 3.
SplineUntangleReport untangle_spline(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                                     const SplineUntangleOptions& options = {});

}  // namespace volspline::spline
