// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>

namespace volspline::volume {

/// Principal directions of a symmetric 3x3 tensor (§5.2.1) as the rows of a rotation matrix.
/// Rows are unit eigenvectors sorted by |eigenvalue| descending (ties: larger signed eigenvalue
/// first, then Eigen's order); rows 0 and 1 have their largest-magnitude component positive (first
/// such component on ties) and row 2 = row 0 x row 1, so the result has determinant +1.
/// `eigenvalues`, if given, receives the eigenvalues in the same order.
/// Precondition: tensor is symmetric and finite.
Eigen::Matrix3d principal_frame(const Eigen::Matrix3d& tensor, Eigen::Vector3d* eigenvalues = nullptr);

/// principal_frame of every tensor (Eq. 5.5 Hessians from fit_local_cubics), same order.
/// threads (>= 1) share the tensors; the frames are the same for every count.
std::vector<Eigen::Matrix3d> hessian_frames(const std::vector<Eigen::Matrix3d>& hessians, int threads = 1);

}  // namespace volspline::volume
