// SPDX-License-Identifier: MIT
#include "core/lens/roi_translation.h"

#include <algorithm>
#include <cmath>

namespace volspline::lens {

namespace {

// Polygon vertices are shifted one by one, so their differences agree only up to rounding.
constexpr double kSameOffset = 1e-9;

}  // namespace

std::optional<Eigen::Vector2d> roi_translation(const std::vector<Roi>& from, const std::vector<Roi>& to) {
  if (from.size() != to.size() || from.empty()) return std::nullopt;
  std::optional<Eigen::Vector2d> offset;
  for (std::size_t i = 0; i < from.size(); ++i) {
    const Roi &a = from[i], &b = to[i];
    if (a.shape != b.shape || a.shape == RoiShape::Mask || a.values.size() != b.values.size() || a.values.size() < 2)
      return std::nullopt;
    const Eigen::Vector2d d(b.values[0] - a.values[0], b.values[1] - a.values[1]);
    if (offset && (d - *offset).cwiseAbs().maxCoeff() > kSameOffset) return std::nullopt;
    offset = d;
    if (a.shape == RoiShape::Polygon) {
      for (std::size_t k = 2; k + 1 < a.values.size(); k += 2)
        if (std::abs(b.values[k] - a.values[k] - d.x()) > kSameOffset ||
            std::abs(b.values[k + 1] - a.values[k + 1] - d.y()) > kSameOffset)
          return std::nullopt;
    } else {
      // Circle radius, rect width and height: the size must be exactly the same.
      for (std::size_t k = 2; k < a.values.size(); ++k)
        if (a.values[k] != b.values[k]) return std::nullopt;
    }
  }
  return offset;
}

PixelBox roi_reach_box(const Roi& roi, double reach) {
  PixelBox box;
  if (roi.shape == RoiShape::Circle) {
    const double r = roi.values[2];
    box = {roi.values[0] - r, roi.values[1] - r, roi.values[0] + r, roi.values[1] + r};
  } else if (roi.shape == RoiShape::Rect) {
    box = {roi.values[0], roi.values[1], roi.values[0] + roi.values[2], roi.values[1] + roi.values[3]};
  } else if (roi.shape == RoiShape::Polygon) {
    box = {roi.values[0], roi.values[1], roi.values[0], roi.values[1]};
    for (std::size_t k = 0; k + 1 < roi.values.size(); k += 2) {
      box.x0 = std::min(box.x0, roi.values[k]), box.x1 = std::max(box.x1, roi.values[k]);
      box.y0 = std::min(box.y0, roi.values[k + 1]), box.y1 = std::max(box.y1, roi.values[k + 1]);
    }
  } else {
    return box;
  }
  return {box.x0 - reach, box.y0 - reach, box.x1 + reach, box.y1 + reach};
}

}  // namespace volspline::lens
