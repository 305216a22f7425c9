// SPDX-License-Identifier: MIT
#include "core/volume/corner_detection.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "core/common/error.h"

namespace volspline::volume {

CornerDetection find_corners(const FrameField& smoothed, const MaterialClassification& classes,
                             const CornerDetectionOptions& options) {
  if (options.ring < 1) throw Error("corner detection: ring must be >= 1, got " + std::to_string(options.ring));
  if (!(options.angle_tol_deg > 0 && options.angle_tol_deg <= 45))
    throw Error("corner detection: angle_tol_deg must be in (0, 45]");
  if (options.max_corners < 0) throw Error("corner detection: max_corners must be >= 0");
  const int nx = smoothed.nx, ny = smoothed.ny, nz = smoothed.nz;
  const std::size_t n = static_cast<std::size_t>(nx) * ny * nz;
  if (classes.nx != nx || classes.ny != ny || classes.nz != nz || classes.label.size() != n || smoothed.frames.size() != n)
    throw Error("corner detection: the frame field and the classification have different grids");

  std::vector<int> constraint_of(n, -1);
  for (std::size_t c = 0; c < classes.constraints.size(); ++c) {
    const std::size_t id = classes.constraints[c].voxel_id;
    if (id >= n) throw Error("corner detection: constraint voxel " + std::to_string(id) + " is outside the grid");
    constraint_of[id] = static_cast<int>(c);
  }
  const double cos_tol = std::cos(options.angle_tol_deg * (3.14159265358979323846 / 180.0));
  const int r = options.ring;
  CornerDetection result;
  std::vector<std::uint8_t> candidate(n, 0);
  // §5.3.1: which axes of the voxel's own frame the constrained normals in its window follow.
  // Only voxels near a constraint can see one; they are found from the constraints' windows.
  std::vector<std::uint8_t> seen(n, 0);
  for (const FrameConstraint& fc : classes.constraints) {
    const int cx = static_cast<int>(fc.voxel_id % nx);
    const int cy = static_cast<int>((fc.voxel_id / nx) % ny);
    const int cz = static_cast<int>(fc.voxel_id / (static_cast<std::size_t>(nx) * ny));
    for (int z = std::max(0, cz - r); z <= std::min(nz - 1, cz + r); ++z)
      for (int y = std::max(0, cy - r); y <= std::min(ny - 1, cy + r); ++y)
        for (int x = std::max(0, cx - r); x <= std::min(nx - 1, cx + r); ++x)
          seen[static_cast<std::size_t>(x) + static_cast<std::size_t>(nx) * (y + static_cast<std::size_t>(ny) * z)] = 1;
  }
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const std::size_t id = static_cast<std::size_t>(x) + static_cast<std::size_t>(nx) * (y + static_cast<std::size_t>(ny) * z);
        if (!seen[id] || classes.label[id] == 0) continue;
        const Eigen::Matrix3d& frame = smoothed.frames[id];
        int axes = 0;
        for (int zz = std::max(0, z - r); zz <= std::min(nz - 1, z + r); ++zz)
          for (int yy = std::max(0, y - r); yy <= std::min(ny - 1, y + r); ++yy)
            for (int xx = std::max(0, x - r); xx <= std::min(nx - 1, x + r); ++xx) {
              const std::size_t other = static_cast<std::size_t>(xx) + static_cast<std::size_t>(nx) * (yy + static_cast<std::size_t>(ny) * zz);
              if (constraint_of[other] < 0) continue;
              const Eigen::Vector3d normal = classes.constraints[constraint_of[other]].normal.normalized();
              for (int a = 0; a < 3; ++a)
                if (std::abs(frame.row(a).dot(normal)) >= cos_tol) axes |= 1 << a;
            }
        const int count = (axes & 1) + ((axes >> 1) & 1) + ((axes >> 2) & 1);
        if (count == 3) {
          candidate[id] = 1;
          result.candidates.push_back(id);
        } else if (count == 2) {
          ++result.num_edge_points;
        }
      }

  // Automatic selection: 26-connected clusters of candidates, largest first.
  struct Cluster {
    std::size_t size;
    std::size_t first;
    std::size_t representative;
  };
  std::vector<Cluster> clusters;
  std::vector<std::uint8_t> done(n, 0);
  std::vector<std::size_t> stack, members;
  for (std::size_t seed : result.candidates) {
    if (done[seed]) continue;
    members.clear();
    stack.assign(1, seed);
    done[seed] = 1;
    while (!stack.empty()) {
      const std::size_t id = stack.back();
      stack.pop_back();
      members.push_back(id);
      const int x = static_cast<int>(id % nx), y = static_cast<int>((id / nx) % ny), z = static_cast<int>(id / (static_cast<std::size_t>(nx) * ny));
      for (int zz = std::max(0, z - 1); zz <= std::min(nz - 1, z + 1); ++zz)
        for (int yy = std::max(0, y - 1); yy <= std::min(ny - 1, y + 1); ++yy)
          for (int xx = std::max(0, x - 1); xx <= std::min(nx - 1, x + 1); ++xx) {
            const std::size_t other = static_cast<std::size_t>(xx) + static_cast<std::size_t>(nx) * (yy + static_cast<std::size_t>(ny) * zz);
            if (candidate[other] && !done[other]) {
              done[other] = 1;
              stack.push_back(other);
            }
          }
    }
    std::sort(members.begin(), members.end());
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    auto position = [&](std::size_t id) {
      return Eigen::Vector3d(static_cast<double>(id % nx), static_cast<double>((id / nx) % ny),
                             static_cast<double>(id / (static_cast<std::size_t>(nx) * ny)));
    };
    for (std::size_t id : members) centroid += position(id);
    centroid /= static_cast<double>(members.size());
    std::size_t best = members.front();
    for (std::size_t id : members)
      if ((position(id) - centroid).squaredNorm() < (position(best) - centroid).squaredNorm()) best = id;
    clusters.push_back({members.size(), members.front(), best});
  }
  std::sort(clusters.begin(), clusters.end(), [](const Cluster& a, const Cluster& b) {
    return a.size != b.size ? a.size > b.size : a.first < b.first;
  });
  const std::size_t keep = options.max_corners == 0 ? clusters.size() : std::min<std::size_t>(clusters.size(), options.max_corners);
  for (std::size_t c = 0; c < keep; ++c) result.corners.push_back(clusters[c].representative);
  std::sort(result.corners.begin(), result.corners.end());
  return result;
}

std::vector<std::size_t> detect_corners(const FrameField& smoothed, const MaterialClassification& classes,
                                        const CornerDetectionOptions& options) {
  return find_corners(smoothed, classes, options).corners;
}

}  // namespace volspline::volume
