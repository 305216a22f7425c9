// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"

namespace volspline::polycube {

/// Length of the level set {h = level} of a function h linear on each triangle of m (one value
/// per vertex).
double level_set_length(const mesh::TriangleMesh& m, const std::vector<double>& h, double level);

/// Where a cap's end face starts (§3.3.2, Algorithm 2), as a fraction of the pole's height
/// `pole_height` (height: distance from the cap's cut loop per vertex). A harmonic map of a
/// region much longer than wide crowds it into a dot, exponentially in that ratio, so the end
/// face must not reach much farther than its own radius: the lowest of 0.5, 0.525, ... whose
/// remaining height (1 − λ)·pole_height is at most 1.5 times its level set's radius (length / 2π;
/// a hemisphere gives 0.5, a long capsule the start of its round end); for a cone that never gets
/// that wide, the highest level two mean edges below the pole (at most 0.95).
double cap_corner_level(const mesh::TriangleMesh& m, const std::vector<double>& height, double pole_height);

/// Four vertices on the front of the level set {h = level} (vertices at or above it with a
/// neighbour below), the i-th at the angle of below[i] about the axis from the front's centroid
/// to `pole`: the upper corners of a limb's cap when the shortest paths from its loop corners to
/// the pole merge before that level. Ids repeat (or are −1) when the front is too small.
std::array<int, 4> front_corners(const mesh::TriangleMesh& m, const std::vector<double>& h, double level,
                                 const Eigen::Vector3d& pole, const std::array<Eigen::Vector3d, 4>& below);

}  // namespace volspline::polycube
