// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/polycube/cube_faces.h"
#include "core/spline/jacobian_certificate.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Options of convex_edge_creases; checked on entry (volspline::Error).
struct EdgeCreaseOptions {
  /// Faces of the domain box on the solid's surface: only edges between two of them are
  /// treated (an edge inside a multi-cuboid solid is no crease).
  polycube::CubeFaceSet exposed_faces = polycube::CubeFaceSet::all();
  /// Scaled Jacobian det J/(|J_a||J_b||J_t|) the first tilt aims for at the edge samples, in
  /// (0, 0.1]: on the edge it is the sine of the crease's angle short of a flat one, so 1e-3
  /// tilts the faces by about 0.06°.
  double margin = 1e-3;
  /// Tilts per edge at most, the margin doubled each time (capped at 0.1), in [1, 16].
  int tries = 7;
  /// Points per cell along the edge where the margin is sought (both ends included), in [2, 64].
  int edge_samples = 9;
};

/// Outcome of convex_edge_creases.
struct EdgeCreaseResult {
  int edges = 0;  ///< (cell, cuboid edge) pairs whose tilt was kept
  int fixed = 0;  ///< of those, the ones whose cell is certified after
  std::vector<int> moved;       ///< the control points moved, increasing
  double max_displacement = 0;  ///< largest move of one control point in one tilt, model units
};

/// Tilts the surface crease along cuboid edges convex where det J is negative on or next to the
/// edge. Not in the thesis: on a cuboid edge along axis t between the faces a and b, the three
/// columns of J depend on bd-control-points (§4.3.1) only: the edge row (J_t) and the rows next
/// to it in face b (J_a) and face a (J_b). Where the surface is smooth the two faces meet at a
/// flat angle and det J = 0 on the edge (the certificate allows it); a fit of a flat region puts
/// the angle a hair past flat and det J < 0 there, which no interior control point can change.
/// Per listed cell and per edge of it between two exposed faces that meet at a near-flat angle
/// (at the middle of the cell's edge the faces' directions across the edge, ±J_a and ±J_b
/// without their parts along J_t, have a cosine below −0.3: a crease, not a cube's right angle,
/// which is left alone) where det J's Bernstein
/// coefficients on the edge line are below −τ (τ: JacobianCertificateOptions::rounding_rel of
/// the cell's column bound), or where the cell's lowest det J (its certificate's lowest corner)
/// lies within half the cell of the edge: the control points of the two rows next to the edge
/// (functions vanishing on the edge whose derivative across it is non-zero) move along the
/// gradient of Σ det J over the edge samples (w·∂B times J's cofactor column: towards the
/// solid's inside), by the least factor that brings every edge sample's scaled Jacobian to the
/// margin. The tilt repeats with twice the margin until the cell is certified, det J's
/// coefficients on the edge are ≥ −τ (the fold left is no crease's), or options.tries tilts are
/// done; it is undone if it neither certifies the cell nor raises the coefficients on the edge.
/// The edge curve stays exactly where it is. cells: e.g. a certificate's uncertified cells, in
/// its order (cells touching no such edge are skipped). Throws volspline::Error if the dimension
/// is not 3 or the options are invalid.
EdgeCreaseResult convex_edge_creases(TSpline& spline, const std::vector<UncertifiedCell>& cells,
                                     const EdgeCreaseOptions& options = {},
                                     const JacobianCertificateOptions& certificate = {});

/// The smallest Bernstein coefficient of det J on the cuboid edge of a cell, divided by the
/// cell's column_bound (so comparable with det_j_lower_bound_rel): the edge along axis t where
/// axis (t + 1) % 3 is at its low (high_a false) or high end and axis (t + 2) % 3 likewise
/// (high_b). Precondition: the cell touches that edge; spline dimension 3.
double edge_lower_bound_rel(const TSpline& spline, int cell, int t, bool high_a, bool high_b);

}  // namespace volspline::spline
