// SPDX-License-Identifier: MIT
// Small synthetic lens inputs shared by the lens and pipeline tests: a checkerboard image and the
// lens mesh of one circular ROI.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/common/image.h"
#include "core/lens/lens_mesh.h"
#include "core/lens/roi.h"
#include "core/lens/roi_field.h"

namespace volspline::test {

/// A w×h grey image of cell×cell squares, 20 and 230 alternating ((0, 0) is 20).
inline Image checkerboard(int w, int h, int cell) {
  Image img{w, h, 1, std::vector<std::uint8_t>(std::size_t(w) * h)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.pixels[y * w + x] = ((x / cell + y / cell) % 2) ? 230 : 20;
  return img;
}

/// The lens mesh of a width×height image with one ROI, `circle` in parse_roi_spec's form
/// ("circle:CX,CY,R", pixels), reaching 0.75 ROI radii into the context: height h0 in ROI
/// inscribed radii, `grid` vertices along the longer side.
inline lens::LensMesh circle_lens_mesh(const std::string& circle, int width, int height, double h0, int grid) {
  const std::vector<lens::RoiField> rois = {
      lens::RoiField::build(lens::parse_roi_spec(circle).roi, width, height, 0.75)};
  lens::LensMeshOptions o;
  o.grid = grid;
  o.height_rel = h0;
  return lens::build_lens_mesh(rois, width, height, o);
}

}  // namespace volspline::test
