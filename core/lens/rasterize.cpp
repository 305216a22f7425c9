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
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const int x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
  const double tx = fx - x0, ty = fy - y0;
  const int ch = image.channels;
  const std::uint8_t* p00 = &image.pixels[(std::size_t(y0) * image.width + x0) * ch];
  const std::uint8_t* p01 = &image.pixels[(std::size_t(y0) * image.width + x1) * ch];
  const std::uint8_t* p10 = &image.pixels[(std::size_t(y1) * image.width + x0) * ch];
  const std::uint8_t* p11 = &image.pixels[(std::size_t(y1) * image.width + x1) * ch];
  for (int c = 0; c < ch; ++c) {
    const double top = p00[c] + tx * (p01[c] - p00[c]);
    const double bottom = p10[c] + tx * (p11[c] - p10[c]);
    // The value lies in [0, 255] as a convex blend of bytes, so no clamp is needed.
    out[c] = static_cast<std::uint8_t>(top + ty * (bottom - top) + 0.5);
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
    // Texture coordinates are affine in the pixel position: uv = t2 + w0·(t0 − t2) + w1·(t1 − t2)
    // with w0 = e1/area2, w1 = e2/area2, so a scanline only adds constant steps.
    const int i0 = triangles(t, 0), i1 = triangles(t, 1), i2 = triangles(t, 2);
    const double inv_area2 = 1.0 / double(area2);
    const double d0u = (texture(i0, 0) - texture(i2, 0)) * inv_area2, d0v = (texture(i0, 1) - texture(i2, 1)) * inv_area2;
    const double d1u = (texture(i1, 0) - texture(i2, 0)) * inv_area2, d1v = (texture(i1, 1) - texture(i2, 1)) * inv_area2;
    const double t2u = texture(i2, 0), t2v = texture(i2, 1);
    // An unmoved triangle (the pinned context) samples every pixel at its own centre, where the
    // bilinear blend is the pixel itself: copy instead.
    bool identity = true;
    for (int k = 0; k < 3 && identity; ++k)
      identity = output(triangles(t, k), 0) == texture(triangles(t, k), 0) &&
                 output(triangles(t, k), 1) == texture(triangles(t, k), 1);
    identity = identity && texture_image.width == width && texture_image.height == height;
    for (int py = y_begin; py <= y_end; ++py) {
      const std::int64_t PY = (std::int64_t(py) << kSubpixelBits) + (1 << (kSubpixelBits - 1));
      const std::int64_t PX = (std::int64_t(x_begin) << kSubpixelBits) + (1 << (kSubpixelBits - 1));
      std::int64_t e[3], step[3];
      for (int k = 0; k < 3; ++k) {
        e[k] = dx[k] * (PY - Y[k]) - dy[k] * (PX - X[k]) + bias[k];  // biased: inside iff all ≥ 0
        step[k] = -dy[k] * std::int64_t(kSubpixel);
      }
      std::uint8_t* row = &image.pixels[std::size_t(py) * width * ch];
      int* row_count = &covered[std::size_t(py) * width];
      for (int px = x_begin; px <= x_end; ++px, e[0] += step[0], e[1] += step[1], e[2] += step[2]) {
        if ((e[0] | e[1] | e[2]) < 0) continue;  // some edge value negative
        if (identity) {
          const std::uint8_t* src = &texture_image.pixels[(std::size_t(py) * width + px) * ch];
          for (int c = 0; c < ch; ++c) row[std::size_t(px) * ch + c] = src[c];
          ++row_count[px];
          continue;
        }
        const double e1 = double(e[1] - bias[1]), e2 = double(e[2] - bias[2]);
        sample_bilinear(texture_image, t2u + e1 * d0u + e2 * d1u, t2v + e1 * d0v + e2 * d1v, row + std::size_t(px) * ch);
        ++row_count[px];
      }
    }
  }
  for (int py = 0; py < height; ++py)
    for (int px = 0; px < width; ++px) {
      const std::size_t pixel = std::size_t(py) * width + px;
      if (covered[pixel]) continue;
      if (px < texture_image.width && py < texture_image.height) {
        for (int c = 0; c < ch; ++c) image.pixels[pixel * ch + c] = texture_image.at(px, py, c);
      } else {
        sample_bilinear(texture_image, px + 0.5, py + 0.5, &image.pixels[pixel * ch]);
      }
    }
  return image;
}

}  // namespace volspline::lens
