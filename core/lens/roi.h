// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

#include "core/common/image.h"

namespace volspline::lens {

/// Shape kinds of a region of interest.
enum class RoiShape { Circle, Rect, Polygon, Mask };

/// One region of interest in pixel coordinates of the input image (x right, y down).
struct Roi {
  RoiShape shape = RoiShape::Circle;
  /// Circle: cx, cy, r. Rect: x, y, w, h (top-left corner and size). Polygon: x1, y1, x2, y2, ...
  /// (at least 3 points, simple). Mask: unused. All in pixels.
  std::vector<double> values;
  /// Mask only: same size as the input image; a pixel whose first channel is ≥ 128 is inside.
  Image mask;
  /// The text the ROI came from (e.g. "circle:100,80,40"), used in error messages.
  std::string name;
};

/// A parsed --roi text: the ROI and, for "mask:FILE", the file to read (empty otherwise).
struct RoiSpec {
  Roi roi;
  std::string mask_path;
};

/// Parses "circle:CX,CY,R", "rect:X,Y,W,H", "polygon:X1,Y1,X2,Y2,..." or "mask:FILE".
/// Throws volspline::Error naming the text on an unknown kind, a bad number or a wrong count.
RoiSpec parse_roi_spec(const std::string& text);

/// Checks a ROI against an image of width × height pixels: positive radius/size, finite values,
/// the shape at least partly inside and its centre inside the image, an area of at most 4 image
/// areas, a mask of the image's size with at least one inside pixel. Throws volspline::Error naming the ROI and the problem.
void validate_roi(const Roi& roi, int width, int height);

}  // namespace volspline::lens
