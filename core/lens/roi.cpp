// SPDX-License-Identifier: MIT
#include "core/lens/roi.h"

#include <cmath>
#include <cstdlib>

#include "core/common/error.h"

namespace volspline::lens {

namespace {

// Largest ROI area, in image areas (a circle through the corners of a square image is 1.57).
constexpr double kMaxRoiCover = 4.0;

std::vector<double> parse_numbers(const std::string& list, const std::string& text) {
  std::vector<double> values;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = list.find(',', start);
    const std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    char* end = nullptr;
    const double value = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(value))
      throw Error("ROI '" + text + "': '" + item + "' is not a number");
    values.push_back(value);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return values;
}

}  // namespace

RoiSpec parse_roi_spec(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos)
    throw Error("ROI '" + text + "': expected circle:CX,CY,R, rect:X,Y,W,H, polygon:X1,Y1,... or mask:FILE");
  const std::string kind = text.substr(0, colon);
  const std::string rest = text.substr(colon + 1);
  RoiSpec spec;
  spec.roi.name = text;
  if (kind == "mask") {
    if (rest.empty()) throw Error("ROI '" + text + "': mask needs a file name");
    spec.roi.shape = RoiShape::Mask;
    spec.mask_path = rest;
    return spec;
  }
  spec.roi.values = parse_numbers(rest, text);
  const std::size_t n = spec.roi.values.size();
  if (kind == "circle") {
    spec.roi.shape = RoiShape::Circle;
    if (n != 3) throw Error("ROI '" + text + "': circle needs 3 numbers CX,CY,R, got " + std::to_string(n));
  } else if (kind == "rect") {
    spec.roi.shape = RoiShape::Rect;
    if (n != 4) throw Error("ROI '" + text + "': rect needs 4 numbers X,Y,W,H, got " + std::to_string(n));
  } else if (kind == "polygon") {
    spec.roi.shape = RoiShape::Polygon;
    if (n < 6 || n % 2 != 0)
      throw Error("ROI '" + text + "': polygon needs at least 3 points X1,Y1,X2,Y2,X3,Y3 (an even count), got " +
                  std::to_string(n) + " numbers");
  } else {
    throw Error("ROI '" + text + "': unknown kind '" + kind + "' (circle, rect, polygon, mask)");
  }
  return spec;
}

void validate_roi(const Roi& roi, int width, int height) {
  const std::string who = "ROI '" + roi.name + "'";
  for (double v : roi.values)
    if (!std::isfinite(v)) throw Error(who + ": values must be finite");
  const auto inside = [&](double x, double y) { return x > 0 && y > 0 && x < width && y < height; };
  // A region far larger than the image leaves no context to compress (the result is one
  // magnified corner or black): refuse areas beyond kMaxRoiCover image areas.
  const auto check_cover = [&](double area) {
    if (!(area <= kMaxRoiCover * double(width) * height))
      throw Error(who + ": covers " + std::to_string(static_cast<long long>(area / (double(width) * height))) +
                  " times the " + std::to_string(width) + "x" + std::to_string(height) + " image (at most " +
                  std::to_string(int(kMaxRoiCover)) + ")");
  };
  switch (roi.shape) {
    case RoiShape::Circle:
      if (roi.values.size() != 3) throw Error(who + ": circle needs CX,CY,R");
      if (roi.values[2] <= 0) throw Error(who + ": radius must be positive");
      if (!inside(roi.values[0], roi.values[1]))
        throw Error(who + ": centre lies outside the " + std::to_string(width) + "x" + std::to_string(height) + " image");
      check_cover(3.14159265358979 * roi.values[2] * roi.values[2]);
      break;
    case RoiShape::Rect:
      if (roi.values.size() != 4) throw Error(who + ": rect needs X,Y,W,H");
      if (roi.values[2] <= 0 || roi.values[3] <= 0) throw Error(who + ": width and height must be positive");
      if (!inside(roi.values[0] + roi.values[2] / 2, roi.values[1] + roi.values[3] / 2))
        throw Error(who + ": centre lies outside the " + std::to_string(width) + "x" + std::to_string(height) + " image");
      check_cover(roi.values[2] * roi.values[3]);
      break;
    case RoiShape::Polygon: {
      const std::size_t n = roi.values.size() / 2;
      if (n < 3 || roi.values.size() % 2 != 0) throw Error(who + ": polygon needs at least 3 points");
      double area2 = 0, cx = 0, cy = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        area2 += roi.values[2 * i] * roi.values[2 * j + 1] - roi.values[2 * j] * roi.values[2 * i + 1];
        cx += roi.values[2 * i] / n;
        cy += roi.values[2 * i + 1] / n;
      }
      if (std::abs(area2) < 2.0) throw Error(who + ": polygon has (nearly) zero area");
      if (!inside(cx, cy))
        throw Error(who + ": centre lies outside the " + std::to_string(width) + "x" + std::to_string(height) + " image");
      check_cover(std::abs(area2) / 2);
      break;
    }
    case RoiShape::Mask: {
      if (roi.mask.width != width || roi.mask.height != height)
        throw Error(who + ": mask is " + std::to_string(roi.mask.width) + "x" + std::to_string(roi.mask.height) +
                    " but the image is " + std::to_string(width) + "x" + std::to_string(height));
      bool any = false;
      for (int y = 0; y < height && !any; ++y)
        for (int x = 0; x < width && !any; ++x) any = roi.mask.at(x, y, 0) >= 128;
      if (!any) throw Error(who + ": mask has no inside pixel (none with value >= 128)");
      break;
    }
  }
}

}  // namespace volspline::lens
