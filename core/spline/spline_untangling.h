// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/common/progress.h"
#include "core/polycube/cube_faces.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Options of untangle_spline.
struct SplineUntangleOptions {
  /// The lattice j/lattice, j = 1 .. lattice−1, per axis of the domain, in [4, 256]: the nodes
  /// themselves if nodes_per_knot_interval is 0, else their least density and the unit of
  /// max_support_steps and the data term.
  int lattice = 48;
  /// Points whose scaled Jacobian is below this seed the untangling, in [0, 1).
  double min_scaled_jacobian = 0.02;
  /// Uniform lattice only: every seed_stride-th lattice node per axis (from the first odd one)
  /// is scanned for seeds, in [1, 4]; 2 scans the 24³ cell centres of the 48 lattice.
  int seed_stride = 2;
  /// Every energy_stride-th lattice node per axis (from the first) is a node, ≥ 1 and a divisor
  /// of seed_stride (so the nodes hold the scanned ones). Knot-interval nodes: at least one
  /// per energy_stride lattice steps.
  int energy_stride = 2;
  /// Least number of nodes per interval of the spline's knot lines (per axis, the centres of
  /// equal parts, at least one per energy_stride lattice steps; all scanned and energy nodes),
  /// ≥ 0; 0: the uniform lattice instead. Knot intervals follow the refinement, so the nodes
  /// are as fine as the finest cells (bunny: 1/64 where the lattice holds 1/24).
  int nodes_per_knot_interval = 1;
  /// Boundary layers: nodes (all scanned) at these fractions of the first (last) node's
  /// distance from the face, at each end of each axis, each in [0, 1); 0 is the face itself
  /// (nodes on the cuboid edges, where det J = 0 by construction, are left out; holding the
  /// faces is slower and unfolds no more points). Folds next to the faces are the normal
  /// derivative on the wrong side of the surface, which the second layer of control points fixes.
  std::vector<double> boundary_layers = {0.25, 0.5};
  /// Faces of the domain box on the solid's surface: the control points of the functions
  /// touching them stay fixed, so the boundary and its surface fit stay as they are.
  polycube::CubeFaceSet exposed_faces = polycube::CubeFaceSet::all();
  /// The box the untangler works on, {min, max} inside the domain, or empty for the whole domain
  /// box. Nodes, checks and the polish lattice lie in it, its faces are the ones exposed_faces
  /// names, and a function whose support is not inside it stays (a GPC cuboid's patch reaches past
  /// its box where a face is continued: those functions belong to the neighbour too). With a
  /// region the certificate rounds are skipped (the certificate covers the whole domain; a GPC
  /// spline runs them over all its cuboids at once: untangle_gpc_certificate).
  std::optional<std::array<Eigen::Vector3d, 2>> region;
  /// Node steps around a seed whose interior functions move, [0, 4]; 0 in the passes after a
  /// dense check (check_per_interval), whose bad points are held themselves.
  int rings = 1;
  /// Only interior functions whose support spans at most this many lattice steps per axis move
  /// (the energy covers their whole supports, so coarse functions would make it global), ≥ 4;
  /// doubled for a seed where such functions carry under a tenth of |w∇B| (they could not
  /// unfold it), and in each further pass if check_per_interval is 0.
  double max_support_steps = 16;
  int passes = 3;              ///< scan + untangle rounds while seeds remain, ≥ 1
  double data_weight = 10.0;   ///< weight of the sample term (unitless ≥ 0), see untangle_spline
  double volume_weight = 0.5;  ///< θ of param::foldover_free_energy, in [0, 1)
  /// ε-continuation steps per pass, ≥ 1; more unfold no more points and cost time.
  int max_steps = 6;
  /// The continuation stops once every scanned node and every node not folded before has
  /// det(J·S⁻¹) above this (S: the reference shape, see untangle_spline), in [0, 1). The dense
  /// checks and the polish find the folds between the nodes, so the passes may stop as soon as
  /// the nodes are unfolded (bench_fold_ensemble: fewer folded points with 0 than with 0.2).
  double stop_margin = 0.0;
  int max_inner = 5;           ///< L-BFGS iterations per step, ≥ 1
  /// Dense check after each pass but the last: the scaled Jacobian at check_per_interval points
  /// per knot interval per axis (centres of equal parts, plus the boundary layers). Its points
  /// below min_scaled_jacobian where the interior functions carry at least a tenth of |w∇B|
  /// seed every later pass and are held there by a hinge W·max(0, min_scaled_jacobian −
  /// det J/σ)² (σ: the column-norm product before the pass; the barrier would stall on those
  /// it cannot lift to its margin); the passes go on while it finds any. ≥ 0; 0: no check, the
  /// passes end once the nodes unfold (and leave folds between them).
  int check_per_interval = 3;
  /// Polish rounds after the passes, ≥ 0: the points of the finest lattice (per axis the
  /// centres of equal parts of the domain as wide as the finest knot interval of any axis, at
  /// least `lattice` of them: bunny's and bimba's 1/64 give the 64³ cell centres, which are the
  /// points of DESIGN.md's negative_jacobian_fraction) with det J ≤ 0 seed a pass whose nodes
  /// are that lattice (no rings, no scan seeds, J evaluated in the box of the free functions'
  /// supports), so the barrier holds every lattice point the free functions touch. Rounds stop
  /// when no lattice point is folded or their number stops falling. Points between the lattice
  /// points are not held: the passes' dense checks are what keeps them few, so the polish comes
  /// after the passes rather than instead of them (finer lattices than the polish's stay folded).
  int polish_rounds = 8;
  int polish_max_per_axis = 128;  ///< cap of the polish lattice per axis, ≥ 2
  /// Least share of a polish round's folded lattice points its pass must unfold, in [0, 1): a
  /// pass that unfolds fewer is undone and the polish stops (0: every pass is kept). Folds the
  /// interior functions barely move (kitten: 42 → 35 in a pass over 200,000 lattice points) are
  /// left to the certificate rounds, whose free functions include the boundary ones.
  double polish_min_unfolded = 0.0;
  /// Certificate rounds after the polish, ≥ 0: the det J certificate (certify_jacobian) of
  /// every cell, whose uncertified cells seed passes like the polish's, held at the points where
  /// each such cell's det J is lowest (its certificate's lowest corner and the negative points of
  /// a 3×3×3 grid on the closed cell, kept from round to round). Interior functions move first;
  /// boundary ones too (kept on the surface by the data term) at points the interior ones
  /// cannot reach (det J on a cuboid edge depends on the boundary alone) and in cells still
  /// uncertified a round later. Rounds stop when every cell is certified or the uncertified
  /// count has not fallen for 3 rounds; the spline of the round with the fewest is kept. Its
  /// cells whose det J is negative on a cuboid edge between two exposed faces then get that
  /// crease tilted convex (convex_edge_creases: there det J depends on the bd-control-points
  /// next to the edge only), kept if fewer cells stay uncertified.
  int certificate_rounds = 8;
  /// In the certificate rounds after one that left no fewer uncertified cells, the factor on
  /// the part of a surface sample's misfit along the surface (normal: the cross product of the
  /// spline's tangents there) in the passes that move boundary functions, in [0, 1]: a face whose
  /// own parameterization folds unfolds by sliding along the surface, which keeps its shape.
  double boundary_tangent_weight = 0.3;
  /// GPC certificate rounds (untangle_gpc_certificate) only: the factor on data_weight for the
  /// samples on the solid's surface (on a cuboid face no other cuboid is glued to) in their first
  /// attempt, ≥ 1. The surface samples are the data the fit is measured against
  /// (hausdorff_rel); the interior ones are the harmonic grid's guess (Eq. 3.1), folded where its
  /// hexes invert, so the rounds should open folds by moving the interior. Where that attempt
  /// leaves cells uncertified, the rounds run again from the start with factor 1.
  double surface_data_factor = 10.0;
  /// GPC certificate rounds (untangle_gpc_certificate) only: how many of its attempts may run,
  /// in [1, 3] (the later ones run only where the earlier leave cells uncertified).
  int certificate_attempts = 3;
};

/// Outcome of untangle_spline.
struct SplineUntangleResult {
  int scanned = 0;            ///< nodes scanned for seeds (and checked after), last pass
  int seeds = 0;              ///< scanned points below min_scaled_jacobian before
  int initial_negative = 0;   ///< scanned points with det J ≤ 0 before
  int final_negative = 0;     ///< and after
  double final_min_scaled = 1.0;  ///< over the scanned points, after
  int free_functions = 0;     ///< interior control points that were free to move
  int points = 0;             ///< energy nodes
  int samples = 0;            ///< samples in the data term
  int iterations = 0;         ///< L-BFGS iterations
  int check_points = 0;       ///< bad points of the dense checks, held in later passes
  int polish_passes = 0;      ///< polish passes run
  int polish_folded = 0;      ///< folded points of the polish lattice at its last scan (0: none)
  int certificate_passes = 0;      ///< passes run by the certificate rounds
  int local_passes = 0;            ///< of those, GPC passes moving their round's cells' functions only
  int initial_uncertified = 0;     ///< uncertified cells before the certificate rounds
  int final_uncertified = 0;       ///< and after (certify_jacobian's count)
  /// Cell edges whose det J was negative on a cuboid edge, tilted convex after the certificate
  /// rounds (convex_edge_creases), and the bd-control-points moved there (0 if the tilt was
  /// undone).
  int crease_edges = 0;
  int crease_functions = 0;
};

/// Unfolds a geometric T-spline (D = 3) near its folds by moving only interior control points
/// (blending functions that vanish on the domain boundary, §4.3.1), so the boundary surface
/// and the surface fit stay exactly as they are. Not in the thesis: the barrier energy of
/// Garanzha et al. 2021 (param::untangle) on the spline's own Jacobians.
///
/// Each pass (untangle_pass.h): nodes per knot interval plus boundary layers; seeds = nodes with
/// scaled Jacobian < min_scaled_jacobian; free = interior functions near the seeds; energy = Σ
/// over the nodes in their supports of param::foldover_free_energy(J·S⁻¹) (S: the node's own J
/// where it is good, else its column lengths) plus data_weight·Σ_s ‖F(uvw_s) − xyz_s‖²/ℓ² (ℓ: one
/// lattice step in model units). Between passes a denser check (check_per_interval) adds the bad
/// points between the nodes, held by a hinge in the later passes; the polish (polish_rounds)
/// then holds the finest lattice.
/// uvw, xyz: m×3 fitting samples (may be empty). Precondition: dimension() == 3.
/// progress: "untangle pass K" / "untangle polish K" / "untangle certificate K: N cells
/// uncertified" before each pass, polish and certificate round (fraction
/// of the passes done); throws volspline::Cancelled there if the callback asks to stop (the
/// spline then holds the points of the passes done so far).
SplineUntangleResult untangle_spline(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                                     const SplineUntangleOptions& options = {}, const Progress& progress = {});

}  // namespace volspline::spline
