// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/common/progress.h"
#include "core/volume/volume.h"

namespace volspline::volume {

/// Options of fit_local_cubics.
struct LocalCubicFitOptions {
  int ring = 2;  ///< k of the k-ring neighbourhood: a (2k+1)^3 voxel window; k >= 2 (k = 1 cannot determine a cubic)
  int threads = 1;  ///< worker threads, >= 1 (1 creates none); every voxel's fit is independent, so the result is the same for every count
};

/// Per-voxel local cubic fit, voxel order as Volume::samples (x fastest).
/// Derivatives are in physical units: per unit of Volume::spacing along each axis.
struct LocalCubicFit {
  int nx = 0;
  int ny = 0;
  int nz = 0;
  std::vector<double> value;             ///< fitted density at the voxel
  std::vector<Eigen::Vector3d> gradient;  ///< (f_x, f_y, f_z) at the voxel
  std::vector<Eigen::Matrix3d> hessian;   ///< symmetric second derivatives at the voxel (Eq. 5.5 tensor)
};

/// Number of cubic monomials u^i v^j w^k with i + j + k <= 3 (20).
constexpr int kNumCubicMonomials = 20;

/// The least-squares operator (Q^T Q)^-1 Q^T of Eq. 5.4 for the (2k+1)^3 window with offsets
/// in [-k, k]^3 (row m: monomial m, ordered by degree; column: window voxel, x fastest).
/// Shape 20 x (2k+1)^3. Precondition: ring >= 2.
Eigen::MatrixXd cubic_fit_operator(int ring);

/// Fits a cubic polynomial (Eq. 5.1) by least squares (Eq. 5.3/5.4) to the (2k+1)^3 window
/// around every voxel and returns value, gradient (Eq. 5.2) and Hessian (Eq. 5.5) at the voxel.
/// Near the border the window is shifted to stay inside the volume and the polynomial is
/// evaluated at the voxel's offset in it, so one operator serves every voxel.
/// Throws volspline::Error if options.ring < 2 or a dimension is smaller than 2k+1.
/// Throws Cancelled if progress asks to stop.
LocalCubicFit fit_local_cubics(const Volume& volume, const LocalCubicFitOptions& options = {},
                               const Progress& progress = {});

}  // namespace volspline::volume
