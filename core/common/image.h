// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <vector>

namespace volspline {

/// An 8-bit raster image: row-major, channels interleaved (1 grey, 3 RGB, 4 RGBA).
/// Pixel (x, y) covers [x, x+1) × [y, y+1) in pixel coordinates (x right, y down).
struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<std::uint8_t> pixels;  ///< width·height·channels bytes

  /// Byte of channel c at pixel (x, y); preconditions: inside the image.
  std::uint8_t at(int x, int y, int c) const {
    return pixels[(static_cast<std::size_t>(y) * width + x) * channels + c];
  }
};

}  // namespace volspline
