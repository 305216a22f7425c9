// SPDX-License-Identifier: MIT
#include "core/param/cuboid_surface_locator.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace volspline::param {

namespace {

int bucket_of(double x, int resolution) {
  return std::clamp(static_cast<int>(x * resolution), 0, resolution - 1);
}

}  // namespace

CuboidSurfaceLocator::CuboidSurfaceLocator(const mesh::HalfedgeMesh& mesh,
                                           const CuboidSurfaceMap& map)
    : positions_(mesh.positions()), triangles_(mesh.triangles()) {
  const int num_faces = mesh.num_faces();
  corner_st_.resize(3 * num_faces);
  std::array<int, 6> count{};
  for (int f = 0; f < num_faces; ++f) {
    const int face = map.face_region[f];
    ++count[face];
    for (int k = 0; k < 3; ++k)
      corner_st_[3 * f + k] = cube_face_coordinates(face, map.uvw.row(triangles_(f, k)).transpose());
  }
  for (int face = 0; face < 6; ++face) {
    FaceIndex& index = faces_[face];
    index.resolution = std::max(1, static_cast<int>(std::sqrt(count[face] / 2.0)));
    const int r = index.resolution;
    std::vector<std::vector<int>> buckets(r * r);
    for (int f = 0; f < num_faces; ++f) {
      if (map.face_region[f] != face) continue;
      Eigen::Vector2d lo = corner_st_[3 * f], hi = corner_st_[3 * f];
      for (int k = 1; k < 3; ++k) {
        lo = lo.cwiseMin(corner_st_[3 * f + k]);
        hi = hi.cwiseMax(corner_st_[3 * f + k]);
      }
      for (int j = bucket_of(lo.y(), r); j <= bucket_of(hi.y(), r); ++j)
        for (int i = bucket_of(lo.x(), r); i <= bucket_of(hi.x(), r); ++i)
          buckets[i + r * j].push_back(f);
    }
    index.bucket_begin.assign(1, 0);
    for (const auto& b : buckets) {
      index.triangles.insert(index.triangles.end(), b.begin(), b.end());
      index.bucket_begin.push_back(static_cast<int>(index.triangles.size()));
    }
  }
}

Eigen::Vector3d CuboidSurfaceLocator::locate(int face, double s, double t) const {
  assert(face >= 0 && face < 6);
  s = std::clamp(s, 0.0, 1.0);
  t = std::clamp(t, 0.0, 1.0);
  const FaceIndex& index = faces_[face];
  const int r = index.resolution;
  const int bucket = bucket_of(s, r) + r * bucket_of(t, r);
  // Best triangle: largest smallest barycentric coordinate (≥ 0 inside; robust on edges).
  double best = -std::numeric_limits<double>::infinity();
  Eigen::Vector3d result = Eigen::Vector3d::Zero();
  const Eigen::Vector2d p(s, t);
  for (int k = index.bucket_begin[bucket]; k < index.bucket_begin[bucket + 1]; ++k) {
    const int f = index.triangles[k];
    const Eigen::Vector2d& a = corner_st_[3 * f];
    const Eigen::Vector2d& b = corner_st_[3 * f + 1];
    const Eigen::Vector2d& c = corner_st_[3 * f + 2];
    const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (area == 0.0) continue;
    const double l1 = ((b - p).x() * (c - p).y() - (b - p).y() * (c - p).x()) / area;
    const double l2 = ((c - p).x() * (a - p).y() - (c - p).y() * (a - p).x()) / area;
    const double l3 = 1.0 - l1 - l2;
    const double smallest = std::min({l1, l2, l3});
    if (smallest > best) {
      best = smallest;
      // Clamp tiny negative coordinates of points on an edge of the square.
      const double c1 = std::max(l1, 0.0), c2 = std::max(l2, 0.0), c3 = std::max(l3, 0.0);
      const double sum = c1 + c2 + c3;
      result = (c1 * positions_.row(triangles_(f, 0)) + c2 * positions_.row(triangles_(f, 1)) +
                c3 * positions_.row(triangles_(f, 2))).transpose() / sum;
      if (smallest >= 0.0) break;
    }
  }
  return result;
}

Eigen::Vector3d CuboidSurfaceLocator::locate_uvw(const Eigen::Vector3d& uvw) const {
  for (int a = 0; a < 3; ++a) {
    if (uvw(a) <= 0.0 || uvw(a) >= 1.0) {
      const int face = 2 * a + (uvw(a) >= 1.0 ? 1 : 0);
      const Eigen::Vector2d st = cube_face_coordinates(face, uvw);
      return locate(face, st.x(), st.y());
    }
  }
  assert(false && "uvw is not on the boundary of the unit cube");
  return Eigen::Vector3d::Zero();
}

}  // namespace volspline::param
