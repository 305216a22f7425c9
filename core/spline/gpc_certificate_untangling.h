// SPDX-License-Identifier: MIT
#pragma once

#include "core/common/progress.h"
#include "core/spline/gpc_spline.h"
#include "core/spline/gpc_spline_fitting.h"
#include "core/spline/jacobian_certificate.h"
#include "core/spline/spline_untangling.h"

namespace volspline::spline {

/// The untangler's certificate rounds (SplineUntangleOptions::certificate_rounds, DESIGN §6)
/// over a whole geometric GPC spline (D = 3), on its global control points: each round
/// certifies every cell of every cuboid box (certify_gpc_jacobian) and holds the points where
/// the uncertified cells fold (uncertified_points: the certificate's lowest corner and the
/// negative points of a 3×3×3 grid on the closed cell; and lowest_jacobian_point, the fold
/// itself, which both can miss; in their cuboid, kept from round to round) by the hinge
/// W·max(0, min_scaled_jacobian − det J/σ)², W multiplied by 8 per round since the uncertified
/// count last fell (a fold the data term holds shut opens once its hinge outweighs it; in the
/// attempts after the first, W is not lowered again when the count falls). The free functions are the
/// global functions whose value or gradient is non-zero at a held point and whose support is at
/// most twice as wide as the narrowest of those per axis (a hierarchical spline's coarser
/// functions would make a pass global), whatever cuboids they reach: a function crossing a Continued face
/// or shared on a Clamped face moves as one control point, so both sides of every glued face stay
/// one surface. The barrier of Garanzha et al. 2021 holds the 2³ centres of equal parts of every
/// knot-line cell (of any cuboid) where a free function is non-zero (where deep splits elsewhere
/// in its cuboid cut one polynomial piece into more than 4 such cells along an axis, the piece's
/// halves along it instead), the hinge also guards the 3×3×3 grid on each such closed cell at
/// no less than min(min_scaled_jacobian, its scaled
/// Jacobian now), and the data term (data_weight per squared knot interval in model units) holds
/// every sample there, which keeps the surface on the mesh; the samples on the solid's surface
/// (on a cuboid face no other cuboid is glued to) are held surface_data_factor times as hard.
/// A round whose uncertified cells' points free at most a fifth of the functions that all the
/// held points free runs a local pass: it moves only the functions at the points of the cells
/// uncertified in its round (the earlier rounds' points still held where those reach them), from
/// the best round's points if its round left more cells uncertified than the best one (a pass
/// over every held point costs in proportion to its functions, and re-folds cells certified
/// already).
/// Rounds stop when every cell is certified or the uncertified count has not fallen for 3
/// rounds; the spline of the round with the fewest is kept. If cells stay uncertified, the
/// rounds run again from the starting points with every sample held alike (if
/// surface_data_factor is not 1), then, if cells still stay uncertified, with every pass
/// local; the attempt with fewer uncertified cells,
/// then the higher det_j_lower_bound_rel, is kept; at most options.certificate_attempts of the
/// three run. Samples: the fit's (cuboid,
/// uvw, xyz) in the spline's frame; their weights are not used. Uses certificate_rounds, min_scaled_jacobian, data_weight,
/// surface_data_factor, volume_weight, max_steps and max_inner of options (each pass's ε continuation runs until its
/// energy settles or max_steps, whatever stop_margin says: the held points are hinge terms,
/// which the barrier nodes' margin does not see); returns certificate_passes, local_passes,
/// free_functions, iterations, initial_uncertified and final_uncertified (the other fields 0).
/// progress: "untangle certificate K: N cells uncertified" before each round; throws
/// volspline::Cancelled there if the callback asks to stop. cache (or null: one of its own): the
/// rounds' certificates, kept for the caller's next certify_gpc_jacobian of the result. Throws
/// volspline::Error if the dimension is not 3.
SplineUntangleResult untangle_gpc_certificate(GpcSpline& spline, const GpcSamples& samples,
                                              const SplineUntangleOptions& options = {},
                                              const Progress& progress = {},
                                              JacobianCertificateCache* cache = nullptr);

}  // namespace volspline::spline
