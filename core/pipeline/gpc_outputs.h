// SPDX-License-Identifier: MIT
#pragma once
// What the CLI and the browser both make of a gpc result: the stats JSON and the segmented
// surface (cuboid per face, poly-edges, corners), so that both write the same keys and bytes.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/pipeline/gpc_job.h"

namespace volspline::pipeline {

/// The poly-edges and corners of every cuboid on its surface, in model units.
struct GpcSegmentation {
  std::vector<std::vector<Eigen::Vector3d>> poly_edges;  ///< 12 polylines per cuboid, cube-edge order
  std::vector<Eigen::Vector3d> corners;                  ///< 8 points per cuboid, cube-corner order
};

/// The poly-edges and corners of result.construction's cuboid surfaces (a corner or edge shared
/// by glued cuboids appears once per cuboid).
GpcSegmentation gpc_segmentation(const GpcResult& result);

/// The segmented GLB of a result (io::serialize_segmented_glb of its refined surface coloured by
/// cuboid, with gpc_segmentation's poly-edges and corners): the bytes `volspline gpc --glb` writes.
std::string gpc_segmentation_glb(const GpcResult& result);

/// The stats JSON of `volspline gpc --stats-json` (GpcStats' fields under DESIGN.md's measure
/// names, times_s per stage in seconds with a total), `input` as its "input" field; 2-space
/// indented, ends in a newline.
std::string gpc_stats_json(const GpcStats& stats, const std::string& input);

}  // namespace volspline::pipeline
