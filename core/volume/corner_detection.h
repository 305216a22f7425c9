// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <vector>

#include "core/volume/frame_field.h"
#include "core/volume/material_classification.h"

namespace volspline::volume {

/// Options of detect_corners.
struct CornerDetectionOptions {
  int ring = 2;                ///< neighbourhood of a voxel: the (2 ring + 1)^3 window, >= 1 (2 reaches past the unconstrained band along sharp edges)
  double angle_tol_deg = 30.0;  ///< a constrained normal counts for a frame axis if within this angle of it, in (0, 45]
  int max_corners = 8;         ///< automatic selection keeps at most this many (largest candidate clusters); 0 = all
};

/// Corner candidates and edge points (§5.3.1).
struct CornerDetection {
  std::vector<std::size_t> candidates;  ///< voxels whose window holds constrained normals along all 3 axes of their frame, sorted
  std::size_t num_edge_points = 0;      ///< voxels whose window holds normals along exactly 2 axes
  std::vector<std::size_t> corners;     ///< the automatic selection: one voxel per 26-connected cluster of candidates, sorted
};

/// Finds corner candidates (§5.3.1): a foreground voxel is a corner candidate when the constrained voxels
/// in its window have normals along 3 different axes of its (smoothed) frame, an edge point when
/// along 2. Automatic selection (the thesis picks interactively): candidates are grouped in
/// 26-connected clusters, the clusters ranked by size (ties: smallest voxel id), and each kept
/// cluster contributes its voxel closest to the cluster centroid (ties: smallest id).
/// Throws volspline::Error on bad options or a grid mismatch between frames and classes.
CornerDetection find_corners(const FrameField& smoothed, const MaterialClassification& classes,
                             const CornerDetectionOptions& options = {});

/// find_corners(...).corners: the selected corner voxels, sorted by flat index.
std::vector<std::size_t> detect_corners(const FrameField& smoothed, const MaterialClassification& classes,
                                        const CornerDetectionOptions& options = {});

}  // namespace volspline::volume
