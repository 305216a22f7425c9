// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "core/common/progress.h"
#include "core/volume/corner_detection.h"
#include "core/volume/frame_field.h"
#include "core/volume/material_classification.h"
#include "core/volume/volume.h"

namespace volspline::volume {

/// Where the corner constraints of compute_field_aligned_param come from.
enum class CornerSelection {
  Automatic,  ///< detect_corners(smoothed, classes, options.corners)
  Given,      ///< options.corner_voxels (the --corners FILE override)
  None,       ///< no corner constraints
};

/// Options of compute_field_aligned_param.
struct FieldAlignedOptions {
  double anisotropy = 0.5;  ///< alpha of Eq. 5.10: weight of the deviation along a coordinate's own frame axis, in (0, 1]; 1 = Eq. 5.7
  int grid_step = 0;        ///< voxels per edge of a parameterization cell, >= 1, or 0 = automatic (smallest step with <= max_grid_nodes nodes)
  int max_grid_nodes = 40000;      ///< bound used by grid_step = 0, >= 8
  double background_weight = 1.0;  ///< weight of background voxels (label 0), whose target is the identity frame, in [0, 1] (0.1 let the background absorb the stretch, which cost density error on tooth)
  /// Frames are trusted near the iso-surface constraints, where they are pinned to a normal:
  /// reliability exp(-(d / R)^2) at Chebyshev distance d (voxels) from the nearest constrained
  /// voxel. R >= 0; 0 = every foreground frame is trusted fully.
  double reliability_radius = 1.0;
  /// Weight of the pull towards the identity frame, times (1 - reliability), on foreground
  /// voxels (a regularisation the thesis leaves open), >= 0.
  double identity_weight = 4.0;
  CornerSelection corner_selection = CornerSelection::Automatic;
  std::vector<std::size_t> corner_voxels;  ///< flat voxel ids for CornerSelection::Given (each < num_voxels)
  CornerDetectionOptions corners;          ///< for CornerSelection::Automatic
  double corner_snap_tol = 0.05;  ///< corner parameters closer than this (uvw units, per coordinate) are snapped to their mean, in [0, 1)
  double corner_weight = 1.0;     ///< penalty of a corner constraint relative to the mean diagonal of the system, > 0 (stronger pins fold the cells around a corner)
  double cg_tolerance = 1e-8;     ///< relative residual of the CG solves, > 0
  int cg_max_iterations = 2000;   ///< >= 1
  int threads = 1;               ///< worker threads, >= 1 (1 creates none): the three coordinate solves run concurrently; the result is the same for every count
};

/// A field-aligned parameterization of the voxel grid (§5.3).
struct FieldAlignedParam {
  Eigen::MatrixX3d uvw;  ///< one row per voxel, flat index x + nx * (y + ny * z), inside [0, 1]^3
  std::vector<std::size_t> corner_voxels;  ///< corners used as constraints, sorted
  Eigen::MatrixX3d corner_uvw;             ///< their snapped target parameters (row per corner)
  double min_jacobian = 0.0;  ///< smallest scaled Jacobian of the voxel hexes mapped to uvw (1 = undistorted cube), over the 8 corners of each hex
  int inverted_cells = 0;     ///< voxel hexes with a corner Jacobian <= 0 in the returned uvw
  int inverted_cells_unblended = 0;  ///< inverted voxel hexes of the solution before the fold fallback
  double identity_blend = 0.0;  ///< mean over voxels of t in the fold fallback uvw = (1 - t) solution + t identity; 0 if the solution had no fold, 1 = identity
  int grid_nx = 0;  ///< nodes of the parameterization grid along x, y, z
  int grid_ny = 0;
  int grid_nz = 0;
  int cg_iterations = 0;   ///< summed over all solves
  bool converged = false;  ///< every CG solve reached cg_tolerance
  double alignment_rms_deg = 0.0;  ///< RMS angle between the gradient of u, v, w and their target frame axes over foreground voxels
  double alignment_rms_deg_identity = 0.0;  ///< the same for the identity map, for comparison
  double alignment_rms_deg_reliable = 0.0;  ///< alignment_rms_deg over foreground voxels with reliability >= 0.5 only
  double alignment_rms_deg_reliable_identity = 0.0;  ///< the same for the identity map
  /// Volume of each voxel hex in uvw (determinant of the mean edge vectors) over its volume under
  /// the identity map: smallest and largest over all hexes (1 = no compression or stretch).
  double volume_ratio_min = 1.0;
  double volume_ratio_max = 1.0;
};

/// Field-aligned parameterization (§5.3) of the whole voxel grid onto [0, 1]^3.
/// Formulation (Eq. 5.7/5.10, gradient operator of Eq. 5.8): the map is a deformation of the
/// identity u = x / ((nx - 1) sx) (likewise v, w): each frame is relabelled by the cube rotation
/// closest to the identity, and the gradient of u is asked to equal row 0 of it scaled by
/// 1 / ((nx - 1) sx) (rows 1, 2 for v, w), with the anisotropic norm of Eq. 5.10; background
/// voxels ask for the identity frame with background_weight; foreground voxels ask for their
/// frame with weight reliability x (how unambiguous that relabelling is: low near 45 degrees,
/// where it jumps) and for the identity frame with identity_weight x (1 - reliability), so the
/// map bends only near the iso-surfaces whose normals fixed the frames (see reliability_radius).
/// The box boundary is held at the
/// identity, so uvw stays in [0, 1]^3 and the solution is unique. Corners get soft constraints
/// at their snapped parameters (corners closer than corner_snap_tol per coordinate share it, so
/// they land on common iso-planes). If the result folds, it is blended with the identity locally
/// around the folded hexes (t = 1 there, falling to 0 at a radius that doubles from 2 voxels
/// until no hex folds; the identity itself as the last resort).
/// Typical use: fit = fit_local_cubics(v); classes = classify_materials(v, fit); opts.active =
/// foreground_mask(classes, 2); smoothed = smooth_frame_field({v.nx, v.ny, v.nz,
/// hessian_frames(fit.hessian)}, classes.constraints, opts).field; then this function.
/// Throws volspline::Error on bad options, grid mismatches, out-of-range corner voxels, or a
/// dimension < 2. Throws Cancelled if progress asks to stop.
FieldAlignedParam compute_field_aligned_param(const Volume& volume, const FrameField& smoothed,
                                              const MaterialClassification& classes,
                                              const FieldAlignedOptions& options = {},
                                              const Progress& progress = {});

/// Scaled-Jacobian check of a per-voxel map (uvw as in FieldAlignedParam) on the voxel hexes:
/// returns the smallest scaled Jacobian over the 8 corners of every hex and sets
/// *inverted (if given) to the number of hexes with a corner Jacobian <= 0. Grid dims >= 2.
double voxel_map_min_jacobian(int nx, int ny, int nz, const Eigen::MatrixX3d& uvw, int* inverted = nullptr);

}  // namespace volspline::volume
