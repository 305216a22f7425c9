// SPDX-License-Identifier: MIT
#include "core/lens/roi_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace volspline::lens {

namespace {

constexpr double kFar = 1e30;
constexpr double kUnset = 1e20;
// Medial-axis cells closer to the boundary than this fraction of the inscribed radius are dropped.
constexpr double kAxisPrune = 0.6;

// Exact 1D squared Euclidean distance transform of f (lower envelope of parabolas); cells
// without a source carry kUnset, a large finite value, so the envelope stays well defined.
void distance_transform_1d(const double* f, int n, double* d, std::vector<int>& v, std::vector<double>& z) {
  int k = 0;
  v[0] = 0;
  z[0] = -kFar;
  z[1] = kFar;
  for (int q = 1; q < n; ++q) {
    double s = ((f[q] + double(q) * q) - (f[v[k]] + double(v[k]) * v[k])) / (2.0 * q - 2.0 * v[k]);
    while (s <= z[k]) {
      --k;
      s = ((f[q] + double(q) * q) - (f[v[k]] + double(v[k]) * v[k])) / (2.0 * q - 2.0 * v[k]);
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = kFar;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const double dq = q - v[k];
    d[q] = dq * dq + f[v[k]];
  }
}

// Euclidean distance (in cells) from every cell to the nearest source cell; kFar if none.
std::vector<double> distance_transform(const std::vector<char>& source, int cols, int rows) {
  std::vector<double> g(source.size());
  for (std::size_t i = 0; i < source.size(); ++i) g[i] = source[i] ? 0.0 : kUnset;
  const int n = std::max(cols, rows);
  std::vector<double> f(n), d(n), z(n + 1);
  std::vector<int> v(n);
  for (int x = 0; x < cols; ++x) {
    for (int y = 0; y < rows; ++y) f[y] = g[std::size_t(y) * cols + x];
    distance_transform_1d(f.data(), rows, d.data(), v, z);
    for (int y = 0; y < rows; ++y) g[std::size_t(y) * cols + x] = d[y];
  }
  for (int y = 0; y < rows; ++y) {
    for (int x = 0; x < cols; ++x) f[x] = g[std::size_t(y) * cols + x];
    distance_transform_1d(f.data(), cols, d.data(), v, z);
    for (int x = 0; x < cols; ++x) g[std::size_t(y) * cols + x] = d[x] >= kUnset / 2 ? kFar : std::sqrt(d[x]);
  }
  return g;
}

bool point_in_polygon(const std::vector<double>& p, double x, double y) {
  const std::size_t n = p.size() / 2;
  bool in = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const double xi = p[2 * i], yi = p[2 * i + 1], xj = p[2 * j], yj = p[2 * j + 1];
    if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) in = !in;
  }
  return in;
}

}  // namespace

RoiField RoiField::build(const Roi& roi, int width, int height, double reach_rel) {
  RoiField field;
  if (roi.shape == RoiShape::Circle) {
    field.is_circle_ = true;
    field.centre_ = {roi.values[0], roi.values[1]};
    field.inscribed_radius_ = roi.values[2];
    field.equivalent_radius_ = roi.values[2];
    return field;
  }
  // Bounding box of the ROI in pixels, clipped to the image, then widened by the reach.
  double bx0 = 0, by0 = 0, bx1 = width, by1 = height;
  if (roi.shape == RoiShape::Rect) {
    bx0 = roi.values[0], by0 = roi.values[1], bx1 = bx0 + roi.values[2], by1 = by0 + roi.values[3];
  } else if (roi.shape == RoiShape::Polygon) {
    bx0 = by0 = kFar, bx1 = by1 = -kFar;
    for (std::size_t i = 0; i + 1 < roi.values.size(); i += 2) {
      bx0 = std::min(bx0, roi.values[i]), bx1 = std::max(bx1, roi.values[i]);
      by0 = std::min(by0, roi.values[i + 1]), by1 = std::max(by1, roi.values[i + 1]);
    }
  }
  bx0 = std::max(bx0, 0.0), by0 = std::max(by0, 0.0);
  bx1 = std::min(bx1, double(width)), by1 = std::min(by1, double(height));
  // Half the box diagonal bounds the equivalent radius, so this margin covers the reach.
  const double margin = std::ceil(reach_rel * 0.5 * std::hypot(bx1 - bx0, by1 - by0)) + 2;
  // One cell of padding beyond the image counts as outside, which clips the ROI to the image.
  field.x0_ = static_cast<int>(std::max(std::floor(bx0 - margin), -1.0));
  field.y0_ = static_cast<int>(std::max(std::floor(by0 - margin), -1.0));
  const int x1 = static_cast<int>(std::min(std::ceil(bx1 + margin), double(width) + 1));
  const int y1 = static_cast<int>(std::min(std::ceil(by1 + margin), double(height) + 1));
  field.cols_ = x1 - field.x0_;
  field.rows_ = y1 - field.y0_;
  const int cols = field.cols_, rows = field.rows_;
  const std::size_t cells = std::size_t(cols) * rows;

  std::vector<char> inside(cells, 0), outside(cells, 0);
  std::size_t area = 0;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const int px = field.x0_ + i, py = field.y0_ + j;
      bool in = false;
      if (px >= 0 && py >= 0 && px < width && py < height) {
        const double x = px + 0.5, y = py + 0.5;
        if (roi.shape == RoiShape::Rect)
          in = x > bx0 && x < bx1 && y > by0 && y < by1;
        else if (roi.shape == RoiShape::Polygon)
          in = point_in_polygon(roi.values, x, y);
        else
          in = roi.mask.at(px, py, 0) >= 128;
      }
      inside[std::size_t(j) * cols + i] = in;
      outside[std::size_t(j) * cols + i] = !in;
      area += in;
    }
  field.equivalent_radius_ = std::sqrt(double(area) / M_PI);

  // Distance to the boundary b; half a cell moves it from cell centres to the cell edge.
  std::vector<double> b = distance_transform(outside, cols, rows);
  std::vector<double> o = distance_transform(inside, cols, rows);
  std::size_t deepest = 0;
  for (std::size_t c = 0; c < cells; ++c) {
    if (inside[c]) b[c] = std::max(b[c] - 0.5, 0.5);
    if (inside[c] && b[c] > b[deepest] + 1e-12) deepest = c;
    if (!inside[deepest] && inside[c]) deepest = c;
  }
  field.centre_ = {field.x0_ + double(deepest % cols) + 0.5, field.y0_ + double(deepest / cols) + 0.5};
  field.inscribed_radius_ = b[deepest];

  // Medial axis: inside cells from which no neighbour climbs b at (nearly) unit slope; elsewhere
  // b grows by one per cell along its gradient, on the axis it cannot.
  std::vector<char> axis(cells, 0);
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const std::size_t c = std::size_t(j) * cols + i;
      if (!inside[c]) continue;
      double climb = 0;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int ni = i + di, nj = j + dj;
          if ((di == 0 && dj == 0) || ni < 0 || nj < 0 || ni >= cols || nj >= rows) continue;
          const std::size_t n = std::size_t(nj) * cols + ni;
          if (!inside[n]) continue;
          climb = std::max(climb, (b[n] - b[c]) / std::sqrt(double(di * di + dj * dj)));
        }
      // Pruned: branches running into convex corners (b → 0) would raise the full lens height
      // right at the boundary, a cliff that folds; §6.3.1 wants the central path only.
      axis[c] = climb < 0.8 && b[c] >= kAxisPrune * b[deepest];
    }
  axis[deepest] = 1;
  const std::vector<double> a = distance_transform(axis, cols, rows);

  field.axis_distance_.assign(cells, 1.0f);
  field.outside_distance_.assign(cells, 0.0f);
  for (std::size_t c = 0; c < cells; ++c) {
    if (inside[c])
      field.axis_distance_[c] = static_cast<float>(a[c] / (a[c] + b[c]));
    else
      field.outside_distance_[c] = static_cast<float>(std::max(o[c] - 0.5, 0.0));
  }
  return field;
}

double RoiField::sample(const std::vector<float>& f, double x, double y, double outside_value) const {
  const double fx = x - x0_ - 0.5, fy = y - y0_ - 0.5;
  if (fx < 0 || fy < 0 || fx > cols_ - 1 || fy > rows_ - 1) return outside_value;
  const int i = std::min(static_cast<int>(fx), cols_ - 2), j = std::min(static_cast<int>(fy), rows_ - 2);
  const double tx = fx - i, ty = fy - j;
  const std::size_t c = std::size_t(j) * cols_ + i;
  return (1 - ty) * ((1 - tx) * f[c] + tx * f[c + 1]) + ty * ((1 - tx) * f[c + cols_] + tx * f[c + cols_ + 1]);
}

double RoiField::axis_distance(double x, double y) const {
  if (is_circle_) return std::min((Eigen::Vector2d(x, y) - centre_).norm() / inscribed_radius_, 1.0);
  return std::min(sample(axis_distance_, x, y, 1.0), 1.0);
}

double RoiField::outside_distance(double x, double y) const {
  if (is_circle_) return std::max((Eigen::Vector2d(x, y) - centre_).norm() - inscribed_radius_, 0.0);
  return sample(outside_distance_, x, y, kFar);
}

}  // namespace volspline::lens
