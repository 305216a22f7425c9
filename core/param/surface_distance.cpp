// SPDX-License-Identifier: MIT
#include "core/param/surface_distance.h"

#include <algorithm>
#include <array>
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

namespace {

// Squared distance from p to the box [lo, hi] (0 inside).
inline double box_distance2(const double* p, const double* lo, const double* hi) {
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double g = std::max({lo[a] - p[a], p[a] - hi[a], 0.0});
    d2 += g * g;
  }
  return d2;
}

// A lower bound skips a box only when it is clearly above the best squared distance, so
// rounding in the bound never hides a triangle that ties.
inline bool farther(double bound2, double best2) { return bound2 * (1.0 - 1e-12) > best2; }

}  // namespace

SurfaceDistance::SurfaceDistance(const mesh::TriangleMesh& mesh) {
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
  auto index = [&](double x, int a) {
    return std::clamp(static_cast<int>((x - origin_(a)) / cell_), 0, size_(a) - 1);
  };
  const int num_faces = mesh.num_faces();
  corners_.resize(9 * std::size_t(num_faces));
  boxes_.resize(6 * std::size_t(num_faces));
  std::vector<std::array<int, 6>> ranges(num_faces);
  std::vector<int> counts(num_buckets + 1, 0);
  for (int f = 0; f < num_faces; ++f) {
    double* c = corners_.data() + 9 * std::size_t(f);
    double* box = boxes_.data() + 6 * std::size_t(f);
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) c[3 * k + a] = mesh.positions(mesh.triangles(f, k), a);
    for (int a = 0; a < 3; ++a) {
      box[a] = std::min({c[a], c[3 + a], c[6 + a]});
      box[3 + a] = std::max({c[a], c[3 + a], c[6 + a]});
      ranges[f][a] = index(box[a], a);
      ranges[f][3 + a] = index(box[3 + a], a);
    }
    for (int z = ranges[f][2]; z <= ranges[f][5]; ++z)
      for (int y = ranges[f][1]; y <= ranges[f][4]; ++y)
        for (int x = ranges[f][0]; x <= ranges[f][3]; ++x) ++counts[x + size_(0) * (y + size_(1) * z) + 1];
  }
  for (int b = 0; b < num_buckets; ++b) counts[b + 1] += counts[b];
  bucket_begin_ = counts;
  bucket_triangles_.resize(counts.back());
  for (int f = 0; f < num_faces; ++f)
    for (int z = ranges[f][2]; z <= ranges[f][5]; ++z)
      for (int y = ranges[f][1]; y <= ranges[f][4]; ++y)
        for (int x = ranges[f][0]; x <= ranges[f][3]; ++x) bucket_triangles_[counts[x + size_(0) * (y + size_(1) * z)]++] = f;
  double area = 0.0;
  for (int f = 0; f < num_faces; ++f) {
    const double* c = corners_.data() + 9 * std::size_t(f);
    const Eigen::Vector3d a(c[0], c[1], c[2]), b(c[3], c[4], c[5]), d(c[6], c[7], c[8]);
    area += 0.5 * (b - a).cross(d - a).norm();
  }
  nearby_radius_ = std::sqrt(area / num_faces);
  bucket_boxes_.resize(6 * bucket_triangles_.size());
  for (std::size_t k = 0; k < bucket_triangles_.size(); ++k)
    std::copy_n(boxes_.data() + 6 * std::size_t(bucket_triangles_[k]), 6, bucket_boxes_.data() + 6 * k);
}

double SurfaceDistance::search(const Eigen::Vector3d& p, double best2, double stop2, Eigen::Vector3d* point,
                               int* face) const {
  Eigen::Vector3i centre;
  for (int a = 0; a < 3; ++a)
    centre(a) = std::clamp(static_cast<int>(std::floor((p(a) - origin_(a)) / cell_)), 0, size_(a) - 1);
  // Distance from p to the grid box, a lower bound for everything in it.
  const Eigen::Vector3d box_hi = origin_ + cell_ * size_.cast<double>();
  const double outside = (origin_ - p).cwiseMax(p - box_hi).cwiseMax(0.0).norm();
  const int max_ring = size_.maxCoeff();
  for (int ring = 0; ring <= max_ring; ++ring) {
    // Everything in ring r is at least (r − 1)·cell away from p (p may sit anywhere in its bucket).
    const double bound = std::max(0.0, (ring - 1) * cell_) + outside;
    if (farther(bound * bound, best2)) break;
    for (int z = std::max(0, centre.z() - ring); z <= std::min(size_(2) - 1, centre.z() + ring); ++z) {
      const bool z_shell = std::abs(z - centre.z()) == ring;
      for (int y = std::max(0, centre.y() - ring); y <= std::min(size_(1) - 1, centre.y() + ring); ++y) {
        const bool yz_shell = z_shell || std::abs(y - centre.y()) == ring;
        // Inside the shell only x = centre ± ring belong to this ring.
        const int step = yz_shell ? 1 : std::max(1, 2 * ring);
        for (int x = centre.x() - ring; x <= centre.x() + ring; x += step) {
          if (x < 0 || x >= size_(0)) continue;
          const double lo[3] = {origin_(0) + x * cell_, origin_(1) + y * cell_, origin_(2) + z * cell_};
          const double hi[3] = {lo[0] + cell_, lo[1] + cell_, lo[2] + cell_};
          if (farther(box_distance2(p.data(), lo, hi), best2)) continue;
          const int b = x + size_(0) * (y + size_(1) * z);
          for (int k = bucket_begin_[b]; k < bucket_begin_[b + 1]; ++k) {
            const double* box = bucket_boxes_.data() + 6 * std::size_t(k);
            if (farther(box_distance2(p.data(), box, box + 3), best2)) continue;
            const int f = bucket_triangles_[k];
            const double* c = corners_.data() + 9 * std::size_t(f);
            const Eigen::Vector3d q = closest_point_on_triangle(p, Eigen::Vector3d(c[0], c[1], c[2]),
                                                                Eigen::Vector3d(c[3], c[4], c[5]),
                                                                Eigen::Vector3d(c[6], c[7], c[8]));
            const double d2 = (q - p).squaredNorm();
            if (d2 < best2) {
              best2 = d2;
              if (point) *point = q;
              if (face) *face = f;
            }
            if (best2 <= stop2) return best2;
          }
        }
      }
    }
  }
  return best2;
}

Eigen::Vector3d SurfaceDistance::closest_point(const Eigen::Vector3d& p, Eigen::Vector3d* normal) const {
  int face = -1;
  return closest_point(p, normal, &face);
}

Eigen::Vector3d SurfaceDistance::closest_point(const Eigen::Vector3d& p, Eigen::Vector3d* normal, int* face) const {
  assert(face && *face < static_cast<int>(boxes_.size() / 6));
  Eigen::Vector3d q = p;
  double best2 = std::numeric_limits<double>::infinity();
  if (*face >= 0) {
    const double* c = corners_.data() + 9 * std::size_t(*face);
    q = closest_point_on_triangle(p, Eigen::Vector3d(c[0], c[1], c[2]), Eigen::Vector3d(c[3], c[4], c[5]),
                                  Eigen::Vector3d(c[6], c[7], c[8]));
    // Just above its distance, so that a tie goes to the triangle closest_point would take.
    best2 = std::nextafter((q - p).squaredNorm(), std::numeric_limits<double>::infinity());
  }
  search(p, best2, -1.0, &q, face);
  if (normal) *normal = face_normal(*face);
  return q;
}

Eigen::Vector3d SurfaceDistance::face_normal(int face) const {
  if (face < 0) return Eigen::Vector3d::Zero();
  const double* c = corners_.data() + 9 * std::size_t(face);
  const Eigen::Vector3d a(c[0], c[1], c[2]), b(c[3], c[4], c[5]), d(c[6], c[7], c[8]);
  const Eigen::Vector3d n = (b - a).cross(d - a);
  return n.norm() > 0.0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
}

double SurfaceDistance::nearest_listed(const Nearby& nearby, const Eigen::Vector3d& p, int hint,
                                       Eigen::Vector3d* point, int* face, bool* tie) const {
  double best2 = std::numeric_limits<double>::infinity();
  *tie = false;
  auto visit = [&](int f, const double* box) {
    if (farther(box_distance2(p.data(), box, box + 3), best2)) return;
    const double* c = corners_.data() + 9 * std::size_t(f);
    const Eigen::Vector3d q = closest_point_on_triangle(p, Eigen::Vector3d(c[0], c[1], c[2]),
                                                        Eigen::Vector3d(c[3], c[4], c[5]), Eigen::Vector3d(c[6], c[7], c[8]));
    const double d2 = (q - p).squaredNorm();
    if (d2 < best2) {
      best2 = d2;
      *point = q;
      *face = f;
      *tie = false;
    } else if (d2 == best2) {
      *tie = true;
    }
  };
  // The hint first: its distance then rules out most boxes.
  if (hint >= 0) visit(hint, &boxes_[6 * std::size_t(hint)]);
  for (std::size_t k = 0; k < nearby.triangles.size(); ++k)
    if (nearby.triangles[k] != hint) visit(nearby.triangles[k], &nearby.boxes[6 * k]);
  return best2;
}

Eigen::Vector3d SurfaceDistance::closest_point(const Eigen::Vector3d& p, Eigen::Vector3d* normal, int* face,
                                               Nearby* nearby) const {
  assert(nearby);
  // A triangle not listed has its box, so itself, farther than radius from the centre, hence
  // farther than radius − |p − centre| from p (margins of 1e-9 cover rounding).
  auto settles = [&](double best2) {
    const double shift = (p - nearby->centre).norm();
    return std::sqrt(best2) * (1.0 + 1e-9) < nearby->radius * (1.0 - 1e-9) - shift * (1.0 + 1e-9);
  };
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (nearby->radius >= 0.0) {
      Eigen::Vector3d q;
      int f = -1;
      bool tie = false;
      const double best2 = nearest_listed(*nearby, p, *face, &q, &f, &tie);
      if (f >= 0 && settles(best2)) {
        if (tie) break;  // the buckets' order decides
        *face = f;
        if (normal) *normal = face_normal(f);
        return q;
      }
    }
    if (attempt > 0) break;
    // Not settled: list the triangles around p.
    nearby->centre = p;
    nearby->radius = nearby_radius_;
    nearby->triangles.clear();
    const double radius2 = nearby_radius_ * nearby_radius_ * (1.0 + 1e-9);
    // The buckets the ball meets (clamped as doubles: p may lie far outside the grid).
    auto bucket_index = [&](double x, int a) {
      return static_cast<int>(std::clamp(std::floor((x - origin_(a)) / cell_), 0.0, double(size_(a) - 1)));
    };
    Eigen::Vector3i lo, hi;
    for (int a = 0; a < 3; ++a) {
      lo(a) = bucket_index(p(a) - nearby_radius_, a);
      hi(a) = bucket_index(p(a) + nearby_radius_, a);
    }
    for (int z = lo(2); z <= hi(2); ++z)
      for (int y = lo(1); y <= hi(1); ++y)
        for (int x = lo(0); x <= hi(0); ++x) {
          const int b = x + size_(0) * (y + size_(1) * z);
          for (int k = bucket_begin_[b]; k < bucket_begin_[b + 1]; ++k)
            if (box_distance2(p.data(), &bucket_boxes_[6 * std::size_t(k)], &bucket_boxes_[6 * std::size_t(k) + 3]) <= radius2)
              nearby->triangles.push_back(bucket_triangles_[k]);
        }
    std::sort(nearby->triangles.begin(), nearby->triangles.end());
    nearby->triangles.erase(std::unique(nearby->triangles.begin(), nearby->triangles.end()), nearby->triangles.end());
    nearby->boxes.resize(6 * nearby->triangles.size());
    for (std::size_t k = 0; k < nearby->triangles.size(); ++k)
      std::copy_n(&boxes_[6 * std::size_t(nearby->triangles[k])], 6, &nearby->boxes[6 * k]);
  }
  return closest_point(p, normal, face);
}

double SurfaceDistance::distance(const Eigen::Vector3d& p) const {
  return std::sqrt(search(p, std::numeric_limits<double>::infinity(), -1.0));
}

double SurfaceDistance::distance_below(const Eigen::Vector3d& p, double limit) const {
  assert(limit >= 0.0);
  const double limit2 = limit * limit;
  const double best2 = search(p, limit2, -1.0);
  return best2 < limit2 ? std::min(limit, std::sqrt(best2)) : limit;
}

bool SurfaceDistance::within(const Eigen::Vector3d& p, double radius) const {
  assert(radius >= 0.0);
  // Only triangles within the radius matter: start the search just above it.
  const double radius2 = radius * radius;
  return search(p, std::nextafter(radius2, std::numeric_limits<double>::infinity()), radius2) <= radius2;
}

}  // namespace volspline::param
