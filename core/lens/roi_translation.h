// SPDX-License-Identifier: MIT
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/lens/roi.h"

namespace volspline::lens {

/// The offset d (pixels) that moves every ROI of `from` onto the ROI of `to` at the same index:
/// same count, shapes and sizes, each value shifted by d (polygon vertices within 1e-9 px).
/// nullopt if the ROIs are not one common translation of each other; masks never match.
std::optional<Eigen::Vector2d> roi_translation(const std::vector<Roi>& from, const std::vector<Roi>& to);

/// Axis-aligned box in pixels, x0 ≤ x1, y0 ≤ y1.
struct PixelBox {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// The ROI's bounding box widened by `reach` pixels on every side: it holds every point whose
/// distance to the ROI is at most `reach` (the lens mesh's free context band, §6.3.1).
/// Precondition: a validated circle, rect or polygon ROI (a mask gives the empty box at 0).
PixelBox roi_reach_box(const Roi& roi, double reach);

}  // namespace volspline::lens
