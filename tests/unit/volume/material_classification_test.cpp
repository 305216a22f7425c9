// SPDX-License-Identifier: MIT
#include "core/volume/material_classification.h"

#include <cmath>
#include <limits>
#include <string>

#include <doctest/doctest.h>

#include "core/common/error.h"

using namespace volspline::volume;

namespace {

// An n^3 volume: `inside` in the box [lo, hi]^3, `outside` elsewhere.
Volume box_volume(int n, int lo, int hi, float inside, float outside) {
  Volume v;
  v.nx = v.ny = v.nz = n;
  v.samples.resize(v.num_voxels());
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const bool in = x >= lo && x <= hi && y >= lo && y <= hi && z >= lo && z <= hi;
        v.samples[v.index(x, y, z)] = in ? inside : outside;
      }
  return v;
}

bool in_box(const Volume& v, std::size_t id, int lo, int hi) {
  const int x = static_cast<int>(id % v.nx), y = static_cast<int>((id / v.nx) % v.ny), z = static_cast<int>(id / (v.nx * v.ny));
  return x >= lo && x <= hi && y >= lo && y <= hi && z >= lo && z <= hi;
}

std::string error_of(const Volume& v, const LocalCubicFit& fit, const ClassificationOptions& options) {
  try {
    classify_materials(v, fit, options);
  } catch (const volspline::Error& e) {
    return e.what();
  }
  return "<no error>";
}

}  // namespace

TEST_CASE("material_classification: k-means separates a two-level box exactly; background is the darker material") {
  const Volume v = box_volume(16, 4, 11, 200.0f, 10.0f);
  const LocalCubicFit fit = fit_local_cubics(v);
  for (int clusters : {2, 0}) {  // given K and automatic K
    ClassificationOptions options;
    options.clusters = clusters;
    const MaterialClassification c = classify_materials(v, fit, options);
    CHECK(c.num_clusters == 2);
    for (std::size_t i = 0; i < v.num_voxels(); ++i) CHECK(c.label[i] == (in_box(v, i, 4, 11) ? 1 : 0));
    CHECK(c.cluster_mean_intensity[0] == doctest::Approx(10.0).epsilon(1e-12));
    CHECK(c.cluster_mean_intensity[1] == doctest::Approx(200.0).epsilon(1e-12));
    CHECK(c.num_foreground == 8u * 8u * 8u);
    if (clusters == 0) CHECK(c.intensity_unexplained.back() < 1e-12);  // two levels: all intensity variance explained
  }
  // A dark box in a bright background: the box is the background (label 0).
  const Volume inverted = box_volume(16, 4, 11, 10.0f, 200.0f);
  ClassificationOptions options;
  options.clusters = 2;
  const MaterialClassification c = classify_materials(inverted, fit_local_cubics(inverted), options);
  for (std::size_t i = 0; i < v.num_voxels(); ++i) CHECK(c.label[i] == (in_box(v, i, 4, 11) ? 0 : 1));
}

TEST_CASE("material_classification: boundary voxels carry the interface normal; iso is a threshold") {
  const Volume v = box_volume(16, 4, 11, 200.0f, 10.0f);
  const LocalCubicFit fit = fit_local_cubics(v);
  ClassificationOptions options;
  options.iso = 100.0;
  const MaterialClassification c = classify_materials(v, fit, options);
  for (std::size_t i = 0; i < v.num_voxels(); ++i) CHECK(c.label[i] == (in_box(v, i, 4, 11) ? 1 : 0));
  CHECK(c.within_sum_squares.empty());
  // The constraints lie on the box's surface voxels (inside, 6-adjacent to the outside), all
  // but those along the sharp edges and corners, where the normal is undefined.
  CHECK(c.constraints.size() < 8u * 8u * 8u - 6u * 6u * 6u);
  int face_centres = 0;
  for (const FrameConstraint& fc : c.constraints) {
    CHECK(in_box(v, fc.voxel_id, 4, 11));
    CHECK(!in_box(v, fc.voxel_id, 5, 10));
    // Face-centre voxels: by symmetry the fitted gradient is along the face normal.
    if (fc.voxel_id == v.index(4, 7, 7) || fc.voxel_id == v.index(11, 8, 7)) {
      CHECK(std::abs(std::abs(fc.normal.normalized().x()) - 1) < 1e-9);
      ++face_centres;
    }
    if (fc.voxel_id == v.index(7, 7, 4)) {
      CHECK(std::abs(std::abs(fc.normal.normalized().z()) - 1) < 1e-9);
      ++face_centres;
    }
    CHECK(fc.voxel_id != v.index(4, 4, 7));  // an edge voxel
  }
  CHECK(face_centres == 3);
  // The foreground mask with a margin of one voxel is the 10^3 box.
  const std::vector<std::uint8_t> mask = foreground_mask(c, 1);
  for (std::size_t i = 0; i < v.num_voxels(); ++i) CHECK(mask[i] == (in_box(v, i, 3, 12) ? 1 : 0));
}

TEST_CASE("material_classification: bad options and mismatched fits are refused with a message") {
  const Volume v = box_volume(8, 2, 5, 1.0f, 0.0f);
  const LocalCubicFit fit = fit_local_cubics(v);
  ClassificationOptions options;
  options.clusters = 1;
  CHECK(error_of(v, fit, options) == "classification: clusters must be 0 (automatic) or in [2, 16], got 1");
  options = {};
  options.texture_ring = 0;
  CHECK(error_of(v, fit, options) == "classification: texture_ring must be >= 1, got 0");
  options = {};
  options.iso = std::numeric_limits<double>::infinity();
  CHECK(error_of(v, fit, options) == "classification: iso must be finite");
  options = {};
  options.sharp_angle_deg = 0;
  CHECK(error_of(v, fit, options) == "classification: sharp_angle_deg must be in (0, 180]");
  const Volume other = box_volume(9, 2, 5, 1.0f, 0.0f);
  CHECK(error_of(other, fit, {}) == "classification: the local cubic fit does not match the volume's 9x9x9 grid");
}
