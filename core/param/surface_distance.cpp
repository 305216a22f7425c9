// SPDX-License-Identifier: MIT
#include "core/param/surface_distance.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace volspline::param {

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0.0)) return a;  // degenerate triangle
  const double v = vb / denom, w = vc / denom;
  return a + v * ab + w * ac;
}

SurfaceDistance::SurfaceDistance(const mesh::TriangleMesh& mesh) : mesh_(mesh) {
  assert(mesh.num_faces() > 0);
  const Eigen::Vector3d lo = mesh.positions.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = mesh.positions.colwise().maxCoeff().transpose();
  const Eigen::Vector3d extent = (hi - lo).cwiseMax(1e-12 * std::max(1.0, (hi - lo).norm()));
  // About num_faces / 2 buckets in the bounding box.
  const double volume = extent.prod();
  cell_ = std::cbrt(volume / std::max(1.0, mesh.num_faces() / 2.0));
  cell_ = std::max(cell_, extent.maxCoeff() / 256.0);
  origin_ = lo;
  for (int a = 0; a < 3; ++a) size_(a) = std::max(1, static_cast<int>(std::ceil(extent(a) / cell_)));
  const int num_buckets = size_.prod();
  std::vector<std::vector<int>> buckets(num_buckets);
  auto index = [&](double x, int a) {
    return std::clamp(static_cast<int>((x - origin_(a)) / cell_), 0, size_(a) - 1);
  };
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Eigen::Vector3d tlo = mesh.positions.row(mesh.triangles(f, 0)).transpose(), thi = tlo;
    for (int k = 1; k < 3; ++k) {
      tlo = tlo.cwiseMin(mesh.positions.row(mesh.triangles(f, k)).transpose());
      thi = thi.cwiseMax(mesh.positions.row(mesh.triangles(f, k)).transpose());
    }
    for (int z = index(tlo.z(), 2); z <= index(thi.z(), 2); ++z)
      for (int y = index(tlo.y(), 1); y <= index(thi.y(), 1); ++y)
        for (int x = index(tlo.x(), 0); x <= index(thi.x(), 0); ++x)
          buckets[x + size_(0) * (y + size_(1) * z)].push_back(f);
  }
  bucket_begin_.assign(1, 0);
  for (const auto& b : buckets) {
    bucket_triangles_.insert(bucket_triangles_.end(), b.begin(), b.end());
    bucket_begin_.push_back(static_cast<int>(bucket_triangles_.size()));
  }
}

double SurfaceDistance::distance(const Eigen::Vector3d& p) const {
  Eigen::Vector3i centre;
  for (int a = 0; a < 3; ++a)
    centre(a) = std::clamp(static_cast<int>(std::floor((p(a) - origin_(a)) / cell_)), 0, size_(a) - 1);
  // Distance from p to the grid box, a lower bound for everything in it.
  const Eigen::Vector3d box_hi = origin_ + cell_ * size_.cast<double>();
  const double outside = (origin_ - p).cwiseMax(p - box_hi).cwiseMax(0.0).norm();
  double best2 = std::numeric_limits<double>::infinity();
  const int max_ring = size_.maxCoeff();
  for (int ring = 0; ring <= max_ring; ++ring) {
    // Everything in ring r is at least (r − 1)·cell away from p (p may sit anywhere in its bucket).
    const double bound = std::max(0.0, (ring - 1) * cell_) + outside;
    if (bound * bound > best2) break;
    for (int z = centre.z() - ring; z <= centre.z() + ring; ++z) {
      if (z < 0 || z >= size_(2)) continue;
      for (int y = centre.y() - ring; y <= centre.y() + ring; ++y) {
        if (y < 0 || y >= size_(1)) continue;
        for (int x = centre.x() - ring; x <= centre.x() + ring; ++x) {
          if (x < 0 || x >= size_(0)) continue;
          if (std::max({std::abs(x - centre.x()), std::abs(y - centre.y()), std::abs(z - centre.z())}) != ring)
            continue;
          const int b = x + size_(0) * (y + size_(1) * z);
          for (int k = bucket_begin_[b]; k < bucket_begin_[b + 1]; ++k) {
            const int f = bucket_triangles_[k];
            const Eigen::Vector3d q = closest_point_on_triangle(
                p, mesh_.positions.row(mesh_.triangles(f, 0)).transpose(),
                mesh_.positions.row(mesh_.triangles(f, 1)).transpose(),
                mesh_.positions.row(mesh_.triangles(f, 2)).transpose());
            best2 = std::min(best2, (q - p).squaredNorm());
          }
        }
      }
    }
  }
  return std::sqrt(best2);
}

}  // namespace volspline::param
