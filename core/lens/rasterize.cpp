// SPDX-License-Identifier: MIT
#include "core/lens/rasterize.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace volspline::lens {

namespace {

constexpr int kSubpixelBits = 8;
constexpr double kSubpixel = 1 << kSubpixelBits;

void sample_bilinear(const Image& image, double u, double v, std::uint8_t* out) {
  const double fx = std::clamp(u - 0.5, 0.0, double(image.width - 1));
  const double fy = std::clamp(v - 0.5, 0.0, double(image.height - 1));
  const int x0 = std::min(static_cast<int>(fx), image.width - 1), y0 = std::min(static_cast<int>(fy), image.height - 1);
  const int x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
  const double tx = fx - x0, ty = fy - y0;
  for (int c = 0; c < image.channels; ++c) {
    const double top = (1 - tx) * image.at(x0, y0, c) + tx * image.at(x1, y0, c);
    const double bottom = (1 - tx) * image.at(x0, y1, c) + tx * image.at(x1, y1, c);
    out[c] = static_cast<std::uint8_t>(std::clamp((1 - ty) * top + ty * bottom + 0.5, 0.0, 255.0));
  }
}

}  // namespace

Image render_textured_mesh(const Image& texture_image, const Eigen::MatrixX2d& output,
                           const Eigen::MatrixX2d& texture, const mesh::Triangles& triangles, int width, int height,
                           std::vector<int>* draw_count) {
  Image image;
  image.width = width;
  image.height = height;
  image.channels = texture_image.channels;
  image.pixels.assign(std::size_t(width) * height * image.channels, 0);
  std::vector<int> local_count;
  std::vector<int>& covered = draw_count ? *draw_count : local_count;
  covered.assign(std::size_t(width) * height, 0);
  const int ch = image.channels;

  for (int t = 0; t < triangles.rows(); ++t) {
    std::int64_t X[3], Y[3];
    for (int k = 0; k < 3; ++k) {
      X[k] = std::llround(output(triangles(t, k), 0) * kSubpixel);
      Y[k] = std::llround(output(triangles(t, k), 1) * kSubpixel);
    }
    const std::int64_t area2 = (X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]);
    if (area2 <= 0) continue;
    // Pixel (px, py) has its centre at (px + 0.5, py + 0.5).
    const auto lo = [](std::int64_t a) { return static_cast<int>(std::floor(double(a) / kSubpixel - 0.5)); };
    const auto hi = [](std::int64_t a) { return static_cast<int>(std::ceil(double(a) / kSubpixel - 0.5)); };
    const int x_begin = std::max(lo(std::min({X[0], X[1], X[2]})), 0);
    const int x_end = std::min(hi(std::max({X[0], X[1], X[2]})), width - 1);
    const int y_begin = std::max(lo(std::min({Y[0], Y[1], Y[2]})), 0);
    const int y_end = std::min(hi(std::max({Y[0], Y[1], Y[2]})), height - 1);
    // Edge k runs from vertex k to k+1; the value is the barycentric weight of vertex k+2 (×area2).
    std::int64_t dx[3], dy[3], bias[3];
    for (int k = 0; k < 3; ++k) {
      dx[k] = X[(k + 1) % 3] - X[k];
      dy[k] = Y[(k + 1) % 3] - Y[k];
      // Top-left rule, antisymmetric in the edge direction so exactly one of two neighbours owns it.
      bias[k] = (dy[k] < 0 || (dy[k] == 0 && dx[k] > 0)) ? 0 : -1;
    }
    const Eigen::Vector2d t0 = texture.row(triangles(t, 0)).transpose();
    const Eigen::Vector2d t1 = texture.row(triangles(t, 1)).transpose();
    const Eigen::Vector2d t2 = texture.row(triangles(t, 2)).transpose();
    for (int py = y_begin; py <= y_end; ++py) {
      const std::int64_t PY = (std::int64_t(py) << kSubpixelBits) + (1 << (kSubpixelBits - 1));
      for (int px = x_begin; px <= x_end; ++px) {
        const std::int64_t PX = (std::int64_t(px) << kSubpixelBits) + (1 << (kSubpixelBits - 1));
        std::int64_t e[3];
        bool inside = true;
        for (int k = 0; k < 3 && inside; ++k) {
          e[k] = dx[k] * (PY - Y[k]) - dy[k] * (PX - X[k]);
          inside = e[k] + bias[k] >= 0;
        }
        if (!inside) continue;
        const double w0 = double(e[1]) / double(area2), w1 = double(e[2]) / double(area2);
        const Eigen::Vector2d uv = w0 * t0 + w1 * t1 + (1.0 - w0 - w1) * t2;
        const std::size_t pixel = std::size_t(py) * width + px;
        sample_bilinear(texture_image, uv.x(), uv.y(), &image.pixels[pixel * ch]);
        ++covered[pixel];
      }
    }
  }
  for (int py = 0; py < height; ++py)
    for (int px = 0; px < width; ++px) {
      const std::size_t pixel = std::size_t(py) * width + px;
      if (!covered[pixel]) sample_bilinear(texture_image, px + 0.5, py + 0.5, &image.pixels[pixel * ch]);
    }
  return image;
}

}  // namespace volspline::lens
