// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/lens/roi.h"

namespace volspline::lens {

/// Distance fields of one ROI (§6.3.1 step 1): the normalized distance to the ROI's medial axis
/// inside, and the distance to the ROI outside. Circles are exact; other shapes are sampled on a
/// one-pixel raster over the ROI's bounding box (exact Euclidean distance transforms) and read
/// back bilinearly. The raster medial axis is pruned to the points at least 0.6 inscribed radii
/// from the boundary, so branches into convex corners do not lift the lens at the boundary.
class RoiField {
 public:
  /// Builds the fields of a validated ROI on a width × height image. The outside distance is kept
  /// at least `reach_rel` equivalent radii beyond the ROI; farther points report a larger value.
  static RoiField build(const Roi& roi, int width, int height, double reach_rel);

  /// Normalized distance d = a/(a+b) at pixel position (x, y), with a the distance to the medial
  /// axis and b the distance to the ROI boundary: 0 on the axis, 1 on the boundary and outside.
  double axis_distance(double x, double y) const;
  /// Distance in pixels from (x, y) to the ROI; 0 inside.
  double outside_distance(double x, double y) const;
  /// The deepest point of the ROI (largest distance to its boundary), pixels.
  Eigen::Vector2d centre() const { return centre_; }
  /// Radius of the largest inscribed circle, pixels.
  double inscribed_radius() const { return inscribed_radius_; }
  /// sqrt(area/π), pixels.
  double equivalent_radius() const { return equivalent_radius_; }

 private:
  double sample(const std::vector<float>& field, double x, double y, double outside_value) const;

  bool is_circle_ = false;
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  double inscribed_radius_ = 0;
  double equivalent_radius_ = 0;
  int x0_ = 0, y0_ = 0, cols_ = 0, rows_ = 0;
  std::vector<float> axis_distance_;     ///< per raster cell
  std::vector<float> outside_distance_;  ///< per raster cell
};

}  // namespace volspline::lens
