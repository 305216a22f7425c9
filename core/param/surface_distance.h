// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"

namespace volspline::param {

/// Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection §5.1.5).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// Unsigned distance from points to a triangle mesh, accelerated by a uniform grid of buckets
/// (exact: rings of buckets are searched until no closer triangle can exist; buckets and
/// triangles whose bounding box is farther than the best distance so far are skipped).
class SurfaceDistance {
 public:
  /// Builds the bucket grid over the mesh's bounding box (about 2 triangles per bucket side).
  /// Precondition: the mesh has at least one triangle and finite positions.
  explicit SurfaceDistance(const mesh::TriangleMesh& mesh);
  /// Distance from p to the nearest point of the mesh, model units.
  double distance(const Eigen::Vector3d& p) const;
  /// min(distance(p), limit), model units; the search only looks closer than limit, so a tight
  /// limit (e.g. a distance known from elsewhere) makes it cheaper. limit >= 0 or +inf.
  double distance_below(const Eigen::Vector3d& p, double limit) const;
  /// True if some point of the mesh is within radius of p (distance(p) <= radius, up to rounding
  /// when they tie); stops at the first such triangle. radius >= 0.
  bool within(const Eigen::Vector3d& p, double radius) const;
  /// The nearest point of the mesh to p (the first of the nearest triangles in bucket order on a
  /// tie) and, if asked, that triangle's unit normal (zero if it is degenerate).
  Eigen::Vector3d closest_point(const Eigen::Vector3d& p, Eigen::Vector3d* normal = nullptr) const;
  /// closest_point for a point near its last projection: *face (a triangle id, or −1 for none)
  /// bounds the search by its own distance to p, so that only triangles as close are examined;
  /// *face gets the nearest triangle. The same point, normal and triangle as closest_point.
  Eigen::Vector3d closest_point(const Eigen::Vector3d& p, Eigen::Vector3d* normal, int* face) const;

  /// The triangles near a point, kept by a caller that projects one moving point again and again.
  struct Nearby {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double radius = -1.0;        ///< every triangle whose box is within radius of centre is listed; < 0: none yet
    std::vector<int> triangles;  ///< ids, increasing
    std::vector<double> boxes;   ///< their bounding boxes (min xyz, max xyz), in that order
  };
  /// closest_point(p, normal, face) with the same point, normal and triangle, cheaper for a point
  /// that moves a little between calls: when the nearest listed triangle is nearer to p than
  /// any unlisted one can be and no other listed triangle is exactly as near, it is the answer
  /// without a search; otherwise as closest_point(p, normal, face), and *nearby is taken again
  /// around p when p has left it.
  Eigen::Vector3d closest_point(const Eigen::Vector3d& p, Eigen::Vector3d* normal, int* face, Nearby* nearby) const;

 private:
  // The triangle's unit normal (zero if it is degenerate).
  Eigen::Vector3d face_normal(int face) const;
  // Nearest of the listed triangles and `hint` (an id or −1) to p: squared distance, point and
  // id; *tie if another of them is exactly as near.
  double nearest_listed(const Nearby& nearby, const Eigen::Vector3d& p, int hint, Eigen::Vector3d* point, int* face,
                        bool* tie) const;

  // Smallest squared distance from p below best2, stopping once it is <= stop2; the point and
  // triangle that reach it, if asked.
  double search(const Eigen::Vector3d& p, double best2, double stop2, Eigen::Vector3d* point = nullptr,
                int* face = nullptr) const;

  std::vector<double> corners_;  // 9 per triangle: a, b, c
  std::vector<double> boxes_;    // 6 per triangle: min xyz, max xyz
  Eigen::Vector3d origin_;
  double cell_ = 1.0;
  Eigen::Vector3i size_;
  std::vector<int> bucket_begin_;
  std::vector<int> bucket_triangles_;
  std::vector<double> bucket_boxes_;  // boxes_ of bucket_triangles_, in their order: one stream per bucket
  double nearby_radius_ = 0.0;         // Nearby::radius: the side of the mean triangle's square
};

}  // namespace volspline::param
