// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/lens/roi_field.h"
#include "core/mesh/triangle_mesh.h"

namespace volspline::lens {

/// Parameters of the lens mesh (§6.3.1).
struct LensMeshOptions {
  int grid = 100;              ///< grid vertices along the longer image side (≥ 4)
  double height_rel = 1.0;     ///< lens height h0, in units of each ROI's inscribed radius (> 0)
  std::vector<double> height_scale;  ///< per ROI: its height is height_rel × height_scale[i] (> 0); empty: 1 each
  double band_rel = 0.75;      ///< width of the free context band around each ROI, in ROI equivalent radii
  double stretch_max = 1.5;    ///< split edges whose 3D length exceeds this multiple of their planar length
  int subdivision_levels = 2;  ///< at most this many rounds of edge splitting
  enum class PinContext { Off, On } pin_context = PinContext::On;  ///< pin every vertex beyond the context band (Off: only the image border)
};

/// The lens mesh: the image grid lifted to a height field over the ROIs, plus split vertices.
struct LensMesh {
  mesh::Positions xyz;        ///< n×3; x, y in pixels of the input image, z the lens height in pixels
  mesh::Triangles triangles;  ///< m×3, positive signed area in (x right, y down) pixel coordinates
  int grid_cols = 0;          ///< the first grid_cols·grid_rows vertices are the grid, row-major
  int grid_rows = 0;
  mesh::Triangles grid_triangles;  ///< the triangles of the unsplit grid (ids of grid vertices)
  std::vector<char> in_roi;        ///< per vertex: strictly inside some ROI (free texture coordinate)
  std::vector<char> pinned;        ///< per vertex: fixed at its (x, y) during flattening
};

/// Builds the regular grid over a width × height image: vertex (i, j) at (W·i/(cols−1), H·j/(rows−1)),
/// cells split into two triangles. Fills xyz (z = 0), triangles, grid_* ; in_roi false, pinned on the border.
LensMesh build_grid(int width, int height, int grid);

/// Lens profile of §6.3.1 step 2 over the normalized medial-axis distance d ∈ [0, 1]: a Gaussian
/// bump, 1 on the axis, 0 (with nearly zero slope) on the boundary.
double lens_profile(double d);

/// Lens height at (x, y): the largest h0·s·r·profile(d) over the ROIs (r their inscribed radius, s
/// their height_scale entry, 1 if `height_scale` is empty), pixels.
double lens_height(const std::vector<RoiField>& rois, double height_rel, const std::vector<double>& height_scale,
                   double x, double y);

/// §6.3.1: lifts the grid to the lens heights, marks ROI vertices, pins the border (and, with
/// pin_context, everything beyond the context band) and splits over-stretched edges (step 3).
/// Preconditions: width, height ≥ 1, options validated, rois non-empty.
LensMesh build_lens_mesh(const std::vector<RoiField>& rois, int width, int height, const LensMeshOptions& options);

}  // namespace volspline::lens
