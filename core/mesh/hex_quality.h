// SPDX-License-Identifier: MIT
#pragma once

#include <array>

#include <Eigen/Core>

namespace volspline::mesh {

/// Scaled Jacobian det J / (|J_0| |J_1| |J_2|) of a 3×3 Jacobian with columns J_a = ∂x/∂u_a,
/// in [−1, 1]; ≤ 0 means folded (or degenerate: −1 when a column is zero).
double scaled_jacobian(const Eigen::Matrix3d& jacobian);

/// Smallest scaled Jacobian det[e1 e2 e3]/(|e1||e2||e3|) over the 8 corners of the hex with
/// corners x[c], c = i + 2j + 4k (the trilinear hex of a grid cell); ≤ 0 means folded.
double hex_min_scaled_jacobian(const std::array<Eigen::Vector3d, 8>& x);

}  // namespace volspline::mesh
