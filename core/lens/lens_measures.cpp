// SPDX-License-Identifier: MIT
#include "core/lens/lens_measures.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <complex>
#include <limits>

#include <Eigen/Geometry>

namespace volspline::lens {

namespace {

double signed_area(const Eigen::MatrixX2d& p, int a, int b, int c) {
  const Eigen::Vector2d u = (p.row(b) - p.row(a)).transpose(), v = (p.row(c) - p.row(a)).transpose();
  return 0.5 * (u.x() * v.y() - u.y() * v.x());
}

double corner_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

}  // namespace

ShapeDistortion measure_distortion(const Eigen::MatrixX2d& output, const Eigen::MatrixX2d& texture,
                                   const mesh::Triangles& triangles) {
  return measure_distortion(output, texture, triangles, std::vector<char>(std::size_t(triangles.rows()), 0));
}

ShapeDistortion measure_distortion(const Eigen::MatrixX2d& output, const Eigen::MatrixX2d& texture,
                                   const mesh::Triangles& triangles, const std::vector<char>& focus) {
  assert(focus.size() == std::size_t(triangles.rows()));
  ShapeDistortion d;
  for (int t = 0; t < triangles.rows(); ++t) {
    const int v[3] = {triangles(t, 0), triangles(t, 1), triangles(t, 2)};
    double e_i = 1.0;
    if (signed_area(output, v[0], v[1], v[2]) <= 0) {
      ++d.flipped_triangles;
    } else {
      // Edges as complex numbers: the best similarity s minimizes Σ|z − s·w|², leaving the
      // residual Σ|z|² − |Σ z·conj(w)|² / Σ|w|².
      std::complex<double> zw = 0;
      double zz = 0, ww = 0;
      for (int e = 0; e < 3; ++e) {
        const int i = v[e], j = v[(e + 1) % 3];
        const std::complex<double> z(output(j, 0) - output(i, 0), output(j, 1) - output(i, 1));
        const std::complex<double> w(texture(j, 0) - texture(i, 0), texture(j, 1) - texture(i, 1));
        zw += z * std::conj(w);
        zz += std::norm(z);
        ww += std::norm(w);
      }
      if (zz > 0 && ww > 0) e_i = std::clamp(1.0 - std::norm(zw) / (zz * ww), 0.0, 1.0);
    }
    d.sum += e_i;
    d.max = std::max(d.max, e_i);
    if (focus[t]) {
      d.sum_focus += e_i;
      d.max_focus = std::max(d.max_focus, e_i);
      ++d.focus_triangles;
    }
  }
  return d;
}

int count_flipped_triangles(const Eigen::MatrixX2d& output, const Eigen::MatrixX2d& texture,
                            const mesh::Triangles& triangles) {
  int flipped = 0;
  for (int t = 0; t < triangles.rows(); ++t) {
    const int a = triangles(t, 0), b = triangles(t, 1), c = triangles(t, 2);
    const double tex = signed_area(texture, a, b, c);
    if (tex == 0) continue;
    const double out = signed_area(output, a, b, c);
    if (tex > 0 ? out <= 0 : out >= 0) ++flipped;
  }
  return flipped;
}

double measure_magnification(const Eigen::MatrixX2d& output, const Eigen::MatrixX2d& texture,
                             const mesh::Triangles& triangles, const Eigen::Vector2d& centre, double radius) {
  double area_out = 0, area_tex = 0, nearest = std::numeric_limits<double>::infinity();
  int nearest_t = -1;
  for (int t = 0; t < triangles.rows(); ++t) {
    const int a = triangles(t, 0), b = triangles(t, 1), c = triangles(t, 2);
    const Eigen::Vector2d centroid = (texture.row(a) + texture.row(b) + texture.row(c)).transpose() / 3.0;
    const double dist = (centroid - centre).norm();
    if (dist < nearest) nearest = dist, nearest_t = t;
    if (dist > radius) continue;
    area_out += signed_area(output, a, b, c);
    area_tex += signed_area(texture, a, b, c);
  }
  if (area_tex <= 0 && nearest_t >= 0) {
    const int a = triangles(nearest_t, 0), b = triangles(nearest_t, 1), c = triangles(nearest_t, 2);
    area_out = signed_area(output, a, b, c);
    area_tex = signed_area(texture, a, b, c);
  }
  return area_tex > 0 && area_out > 0 ? std::sqrt(area_out / area_tex) : 0.0;
}

double edge_length_error(const mesh::Positions& xyz, const Eigen::MatrixX2d& output, const mesh::Triangles& triangles) {
  double sum = 0;
  for (int t = 0; t < triangles.rows(); ++t)
    for (int e = 0; e < 3; ++e) {
      const int i = triangles(t, e), j = triangles(t, (e + 1) % 3);
      sum += std::abs((output.row(j) - output.row(i)).norm() / (xyz.row(j) - xyz.row(i)).norm() - 1.0);
    }
  return triangles.rows() > 0 ? sum / (3.0 * triangles.rows()) : 0.0;
}

double angle_error(const mesh::Positions& xyz, const Eigen::MatrixX2d& output, const mesh::Triangles& triangles) {
  double sum = 0;
  for (int t = 0; t < triangles.rows(); ++t)
    for (int c = 0; c < 3; ++c) {
      const int i = triangles(t, c), j = triangles(t, (c + 1) % 3), k = triangles(t, (c + 2) % 3);
      const double rest = corner_angle((xyz.row(j) - xyz.row(i)).transpose(), (xyz.row(k) - xyz.row(i)).transpose());
      Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
      a.head<2>() = (output.row(j) - output.row(i)).transpose();
      b.head<2>() = (output.row(k) - output.row(i)).transpose();
      sum += std::abs(corner_angle(a, b) - rest);
    }
  return triangles.rows() > 0 ? sum / (3.0 * triangles.rows()) : 0.0;
}

}  // namespace volspline::lens
