// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/common/progress.h"

namespace volspline::volume {

/// One frame per voxel of an nx x ny x nz grid (x fastest). Each frame is a rotation matrix whose
/// rows are the three orthonormal directions f0, f1, f2 (§5.2.2). frames.size() == nx * ny * nz.
struct FrameField {
  int nx = 0;
  int ny = 0;
  int nz = 0;
  std::vector<Eigen::Matrix3d> frames;
};

/// A voxel one of whose frame axes must lie along `normal` (an iso-surface normal, §5.2.2).
struct FrameConstraint {
  std::size_t voxel_id = 0;  ///< flat index x + nx * (y + ny * z)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< non-zero; normalized on use
};

/// The 24 rotations of the cube group (signed permutation matrices with determinant +1), the
/// identity first, in a fixed order.
const std::array<Eigen::Matrix3d, 24>& cube_group_rotations();

/// Jump-matched squared distance between two frames (Eq. 5.6 term of one edge):
/// min over the 24 cube rotations g of ||a - g b||_F^2. Symmetric in a and b; in [0, 6].
/// If `best` is given it receives a minimizing g (a fixed choice on ties).
double frame_distance_squared(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, Eigen::Matrix3d* best = nullptr);

/// Eq. 5.6 with jump matching: the sum of frame_distance_squared over all 6-neighbour voxel pairs
/// (if `active` is not null: one entry per voxel, only pairs of two voxels with a non-zero entry).
/// threads >= 1: z planes are summed in parallel; the result is the same for every count.
double frame_smoothness_energy(const FrameField& field, const std::vector<std::uint8_t>* active = nullptr, int threads = 1);

/// Starting field of smooth_frame_field.
enum class FrameInitialization {
  Given,       ///< the frames passed in (Hessian principal frames, §5.2.1), as the thesis does
  Propagated,  ///< frames grown outward from the constrained voxels in breadth-first order, each the registration of its already-grown neighbours; voxels no constraint reaches keep the given frame
};

/// Options of smooth_frame_field.
struct FrameSmoothingOptions {
  FrameInitialization initialization = FrameInitialization::Propagated;  ///< Propagated reaches a lower Eq. 5.6 on every test volume
  int max_iterations = 200;               ///< sweeps over all voxels, >= 1
  double energy_decrease_tol_rel = 1e-3;  ///< stop when one sweep lowers Eq. 5.6 by less than this fraction (>= 0)
  /// Empty: every voxel is smoothed. Otherwise one entry per voxel: 1 = smoothed, 0 = kept as
  /// given and left out of Eq. 5.6 (only edges between two active voxels count), e.g.
  /// foreground_mask(classes, margin). Constraints on inactive voxels are ignored.
  std::vector<std::uint8_t> active;
  int threads = 1;  ///< worker threads (>= 1); the result is the same for every count
};

/// Result of smooth_frame_field.
struct FrameSmoothingResult {
  FrameField field;
  double initial_energy = 0.0;  ///< Eq. 5.6 (active voxels) of the given frames with constrained axes rotated onto their normals: the field the thesis starts from
  double start_energy = 0.0;    ///< Eq. 5.6 after the initialization (== initial_energy for FrameInitialization::Given); the sweeps never raise it
  double final_energy = 0.0;    ///< Eq. 5.6 of `field`
  std::vector<double> energy_per_iteration;  ///< Eq. 5.6 after each sweep, non-increasing from start_energy
  int iterations = 0;
  bool converged = false;                  ///< the relative decrease fell below the tolerance
  double max_constraint_angle_rad = 0.0;   ///< largest angle between a normal and its closest frame axis line
};

/// Smooths a frame field (§5.2.2). First every constrained voxel's frame is rotated by the
/// smallest rotation taking its closest axis onto the normal, and the field is initialized (see
/// FrameInitialization). Then Gauss-Seidel sweeps in voxel order inside slabs of 4 z planes,
/// forward and backward in turn (symmetric Gauss-Seidel), the even slabs in parallel, then the
/// odd ones (reversed on backward sweeps), skipping voxels whose neighbourhood has not moved: each voxel's frame is registered to its 6 neighbours' frames with jump matching over
/// the 24 cube rotations (matching the 6 frame end points), and replaced by the rotation of the
/// polar decomposition of the matched covariance; for a constrained voxel the same registration
/// is solved with one axis held on its normal. Each update cannot raise Eq. 5.6, so the energy
/// never increases across sweeps. Stops when a sweep lowers the energy by less than
/// energy_decrease_tol_rel (relative), when it is below 1e-8 per active voxel, or at max_iterations.
/// Only active voxels (options.active) are updated; see FrameInitialization for the start.
/// Throws volspline::Error on bad options, a frame count that does not match the grid, a
/// non-rotation frame, or a constraint with an out-of-range voxel, a zero normal or a voxel
/// that already has a constraint (only one axis per voxel can be constrained).
/// Throws Cancelled if progress asks to stop.
FrameSmoothingResult smooth_frame_field(const FrameField& initial, const std::vector<FrameConstraint>& constraints,
                                        const FrameSmoothingOptions& options = {},
                                        const Progress& progress = {});

}  // namespace volspline::volume
