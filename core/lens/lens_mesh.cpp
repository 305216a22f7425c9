// SPDX-License-Identifier: MIT
#include "core/lens/lens_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace volspline::lens {

LensMesh build_grid(int width, int height, int grid) {
  LensMesh m;
  const int longer = std::max(width, height), shorter = std::min(width, height);
  const int short_count = std::max(4, static_cast<int>(std::lround(double(grid - 1) * shorter / longer)) + 1);
  m.grid_cols = width >= height ? grid : short_count;
  m.grid_rows = width >= height ? short_count : grid;
  const int cols = m.grid_cols, rows = m.grid_rows;
  m.xyz.resize(std::size_t(cols) * rows, 3);
  m.pinned.assign(std::size_t(cols) * rows, 0);
  m.in_roi.assign(std::size_t(cols) * rows, 0);
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const int v = j * cols + i;
      m.xyz.row(v) << double(width) * i / (cols - 1), double(height) * j / (rows - 1), 0.0;
      m.pinned[v] = i == 0 || j == 0 || i == cols - 1 || j == rows - 1;
    }
  m.triangles.resize(std::size_t(2) * (cols - 1) * (rows - 1), 3);
  int t = 0;
  for (int j = 0; j + 1 < rows; ++j)
    for (int i = 0; i + 1 < cols; ++i) {
      const int a = j * cols + i, b = a + 1, c = a + cols + 1, d = a + cols;
      // Alternate the diagonal so the grid has no preferred direction (a lens is round).
      if ((i + j) % 2 == 0) {
        m.triangles.row(t++) << a, b, c;
        m.triangles.row(t++) << a, c, d;
      } else {
        m.triangles.row(t++) << a, b, d;
        m.triangles.row(t++) << b, c, d;
      }
    }
  m.grid_triangles = m.triangles;
  return m;
}

double lens_profile(double d) {
  // §6.3.1 prints h = g(1−d)·h0 with "the standard gaussian g(x) = e^{x²}", which is not zero on the
  // boundary; we use a Gaussian bump in d (σ = 0.45) shifted and scaled to 1 on the axis and 0 on
  // the boundary: a plateau around the axis that the harmonic texture shrinks (the magnification).
  // σ = 0.45 gave the lowest distortion_max over σ ∈ {0.25 … 0.6} (camera.png, circle, grids 100/200).
  constexpr double kSigma = 0.45;
  const double floor = std::exp(-0.5 / (kSigma * kSigma));
  const double x = std::clamp(d, 0.0, 1.0);
  return (std::exp(-0.5 * x * x / (kSigma * kSigma)) - floor) / (1.0 - floor);
}

double lens_height(const std::vector<RoiField>& rois, double height_rel, const std::vector<double>& height_scale,
                   double x, double y) {
  double h = 0;
  for (std::size_t i = 0; i < rois.size(); ++i) {
    const RoiField& roi = rois[i];
    const double d = roi.axis_distance(x, y);
    const double scale = height_scale.empty() ? 1.0 : height_scale[i];
    if (d < 1.0) h = std::max(h, height_rel * scale * roi.inscribed_radius() * lens_profile(d));
  }
  return h;
}

LensMesh build_lens_mesh(const std::vector<RoiField>& rois, int width, int height, const LensMeshOptions& options) {
  LensMesh m = build_grid(width, height, options.grid);
  const auto classify = [&](int v) {
    const double x = m.xyz(v, 0), y = m.xyz(v, 1);
    bool in = false, near = false;
    for (const RoiField& roi : rois) {
      in = in || roi.axis_distance(x, y) < 1.0;
      near = near || roi.outside_distance(x, y) <= options.band_rel * roi.equivalent_radius();
    }
    m.in_roi[v] = in && !m.pinned[v];
    if (options.pin_context == LensMeshOptions::PinContext::On && !near) m.pinned[v] = 1;
    m.xyz(v, 2) = m.pinned[v] ? 0.0 : lens_height(rois, options.height_rel, options.height_scale, x, y);
  };
  for (int v = 0; v < m.xyz.rows(); ++v) classify(v);

  // §6.3.1 step 3: split over-stretched edges. Thesis interpolates heights linearly; we evaluate
  // the lens height at the new vertex so splitting also refines the surface, not only the mesh.
  const double planar_min = 0.26 * double(width) / (m.grid_cols - 1);
  for (int level = 0; level < options.subdivision_levels; ++level) {
    const int n = static_cast<int>(m.xyz.rows());
    std::unordered_map<std::uint64_t, int> midpoint;
    std::vector<Eigen::Vector3d> added;
    const auto key = [n](int a, int b) { return std::uint64_t(std::min(a, b)) * n + std::max(a, b); };
    // Only triangles with a stretched edge consult the midpoint map below (most of the grid is flat).
    const auto stretched = [&](int a, int b) {
      const double dz = m.xyz(b, 2) - m.xyz(a, 2);
      if (dz == 0.0) return false;
      const double planar2 = (m.xyz.row(b).head<2>() - m.xyz.row(a).head<2>()).squaredNorm();
      return planar2 >= planar_min * planar_min && planar2 + dz * dz > options.stretch_max * options.stretch_max * planar2;
    };
    std::vector<char> touched(static_cast<std::size_t>(m.triangles.rows()), 0);
    for (int t = 0; t < m.triangles.rows(); ++t)
      for (int e = 0; e < 3; ++e) {
        const int a = m.triangles(t, e), b = m.triangles(t, (e + 1) % 3);
        if (!stretched(a, b)) continue;
        touched[t] = 1;
        if (midpoint.emplace(key(a, b), n + static_cast<int>(added.size())).second)
          added.push_back(0.5 * (m.xyz.row(a) + m.xyz.row(b)).transpose());
      }
    if (added.empty()) break;
    m.xyz.conservativeResize(n + static_cast<Eigen::Index>(added.size()), 3);
    m.pinned.resize(m.xyz.rows(), 0);
    m.in_roi.resize(m.xyz.rows(), 0);
    for (std::size_t k = 0; k < added.size(); ++k) {
      m.xyz.row(n + static_cast<Eigen::Index>(k)) = added[k].transpose();
      classify(n + static_cast<int>(k));
    }
    std::vector<Eigen::Vector3i> out;
    out.reserve(m.triangles.rows() * 2);
    for (int t = 0; t < m.triangles.rows(); ++t) {
      int v[3] = {m.triangles(t, 0), m.triangles(t, 1), m.triangles(t, 2)};
      int mid[3] = {-1, -1, -1};
      int count = 0;
      for (int e = 0; e < 3 && touched[t]; ++e) {
        auto it = midpoint.find(key(v[e], v[(e + 1) % 3]));
        mid[e] = it == midpoint.end() ? -1 : it->second;
        count += mid[e] >= 0;
      }
      if (count == 0) {
        out.emplace_back(v[0], v[1], v[2]);
      } else if (count == 3) {
        out.emplace_back(v[0], mid[0], mid[2]);
        out.emplace_back(mid[0], v[1], mid[1]);
        out.emplace_back(mid[2], mid[1], v[2]);
        out.emplace_back(mid[0], mid[1], mid[2]);
      } else if (count == 1) {
        const int e = mid[0] >= 0 ? 0 : mid[1] >= 0 ? 1 : 2;
        const int a = v[e], b = v[(e + 1) % 3], c = v[(e + 2) % 3], ab = mid[e];
        out.emplace_back(a, ab, c);
        out.emplace_back(ab, b, c);
      } else {
        const int e = mid[0] < 0 ? 0 : mid[1] < 0 ? 1 : 2;  // the unsplit edge is (v[e], v[e+1])
        const int a = v[e], b = v[(e + 1) % 3], c = v[(e + 2) % 3];
        const int bc = mid[(e + 1) % 3], ca = mid[(e + 2) % 3];
        out.emplace_back(ca, bc, c);
        // Split the remaining quad a-b-bc-ca along its shorter diagonal.
        const double d1 = (m.xyz.row(a) - m.xyz.row(bc)).norm(), d2 = (m.xyz.row(b) - m.xyz.row(ca)).norm();
        if (d1 <= d2) {
          out.emplace_back(a, b, bc);
          out.emplace_back(a, bc, ca);
        } else {
          out.emplace_back(a, b, ca);
          out.emplace_back(b, bc, ca);
        }
      }
    }
    m.triangles.resize(static_cast<Eigen::Index>(out.size()), 3);
    for (std::size_t t = 0; t < out.size(); ++t) m.triangles.row(static_cast<Eigen::Index>(t)) = out[t].transpose();
  }
  return m;
}

}  // namespace volspline::lens
