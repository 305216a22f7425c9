// SPDX-License-Identifier: MIT
#pragma once

#include <array>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"

namespace volspline::mesh {

/// Scaled Jacobian det J / (|J_0| |J_1| |J_2|) of a 3×3 Jacobian with columns J_a = ∂x/∂u_a,
/// in [−1, 1]; ≤ 0 means folded (or degenerate: −1 when a column is zero).
double scaled_jacobian(const Eigen::Matrix3d& jacobian);

/// Smallest scaled Jacobian det[e1 e2 e3]/(|e1||e2||e3|) over the 8 corners of the hex with
/// corners x[c], c = i + 2j + 4k (the trilinear hex of a grid cell); ≤ 0 means folded.
double hex_min_scaled_jacobian(const std::array<Eigen::Vector3d, 8>& x);

/// The principal axes of the hex (Verdict's centre Jacobian): column a is the sum of the 4 edges
/// along axis a, x[c | a-bit] − x[c].
Eigen::Matrix3d hex_principal_axes(const std::array<Eigen::Vector3d, 8>& x);

/// The hex scaled Jacobian as VTK (vtkMeshQuality's HexScaledJacobian, after Verdict) and
/// ParaView report it: hex_min_scaled_jacobian and, at the centre, the scaled Jacobian of the
/// principal axes (the sums of the 4 edges along each axis), the least of the 9. The measure the
/// stats and files report, so that they agree with what those tools show.
double hex_scaled_jacobian(const std::array<Eigen::Vector3d, 8>& x);

/// Hex counts of a structured grid: node (i, j, k) at row i + n0·(j + n1·k) of xyz.
struct HexGridQuality {
  int num_hexes = 0;
  int num_inverted = 0;            ///< hexes with hex_scaled_jacobian ≤ 0
  double min_scaled_jacobian = 1.0;
};
HexGridQuality hex_grid_quality(const std::array<int, 3>& nodes, const Positions& xyz);

}  // namespace volspline::mesh
