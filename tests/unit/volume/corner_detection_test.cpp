// SPDX-License-Identifier: MIT
#include "core/volume/corner_detection.h"

#include <string>

#include <Eigen/Geometry>
#include <doctest/doctest.h>

#include "core/common/error.h"

using namespace volspline::volume;

namespace {

// Classification of an n^3 grid with the material box [lo, hi]^3 and a constraint on every box
// face voxel (not on an edge, as classify_materials leaves sharp features out) with its face normal.
MaterialClassification box_classes(int n, int lo, int hi) {
  MaterialClassification c;
  c.nx = c.ny = c.nz = n;
  c.num_clusters = 2;
  c.label.assign(static_cast<std::size_t>(n) * n * n, 0);
  for (int z = lo; z <= hi; ++z)
    for (int y = lo; y <= hi; ++y)
      for (int x = lo; x <= hi; ++x) {
        const std::size_t id = x + static_cast<std::size_t>(n) * (y + static_cast<std::size_t>(n) * z);
        c.label[id] = 1;
        const Eigen::Vector3d normal((x == hi) - (x == lo), (y == hi) - (y == lo), (z == hi) - (z == lo));
        if (normal.squaredNorm() == 1) c.constraints.push_back({id, normal});
      }
  return c;
}

FrameField identity_field(int n) {
  return FrameField{n, n, n, std::vector<Eigen::Matrix3d>(static_cast<std::size_t>(n) * n * n, Eigen::Matrix3d::Identity())};
}

}  // namespace

TEST_CASE("corner_detection: the 8 corners of a box are found, edges are edge points") {
  const int n = 16, lo = 4, hi = 11;
  const MaterialClassification classes = box_classes(n, lo, hi);
  const FrameField field = identity_field(n);
  const CornerDetection found = find_corners(field, classes);
  // Candidates: box voxels whose 5^3 window reaches the face voxels of three faces, which
  // happens only next to a box corner; one is selected per corner.
  CHECK(!found.candidates.empty());
  for (std::size_t id : found.candidates) {
    const int x = static_cast<int>(id % n), y = static_cast<int>((id / n) % n), z = static_cast<int>(id / (n * n));
    for (int p : {x, y, z}) CHECK((p <= lo + 2 || p >= hi - 2));
  }
  CHECK(found.num_edge_points > 0);
  REQUIRE(found.corners.size() == 8);
  int octants = 0;
  for (std::size_t id : found.corners) {
    const int x = static_cast<int>(id % n), y = static_cast<int>((id / n) % n), z = static_cast<int>(id / (n * n));
    octants |= 1 << ((x > n / 2) + 2 * (y > n / 2) + 4 * (z > n / 2));
  }
  CHECK(octants == 255);
  CHECK(detect_corners(field, classes) == found.corners);
  // max_corners limits the selection, and frames rotated by a cube rotation change nothing.
  CornerDetectionOptions options;
  options.max_corners = 3;
  CHECK(detect_corners(field, classes, options).size() == 3);
  FrameField rotated = field;
  for (auto& f : rotated.frames) f = cube_group_rotations()[7];
  CHECK(detect_corners(rotated, classes) == found.corners);
  // Normals at 40 degrees to every axis of a rotated frame count for no axis: no candidate.
  FrameField skew = field;
  for (auto& f : skew.frames) f = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 1).normalized()).toRotationMatrix();
  options = {};
  options.angle_tol_deg = 5;
  CHECK(find_corners(skew, classes, options).candidates.empty());
}

TEST_CASE("corner_detection: bad options are refused with a message") {
  const MaterialClassification classes = box_classes(6, 1, 4);
  CornerDetectionOptions options;
  options.ring = 0;
  std::string message;
  try {
    find_corners(identity_field(6), classes, options);
  } catch (const volspline::Error& e) {
    message = e.what();
  }
  CHECK(message == "corner detection: ring must be >= 1, got 0");
  message.clear();
  try {
    find_corners(identity_field(5), classes);
  } catch (const volspline::Error& e) {
    message = e.what();
  }
  CHECK(message == "corner detection: the frame field and the classification have different grids");
}
