// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "core/lens/lens_mesh.h"

namespace volspline::lens {

/// Texture coordinates of the lens mesh (§6.3.2): every vertex outside the ROIs (and on the image
/// border) keeps its (x, y); ROI vertices solve the harmonic equations Δu = Δv = 0 discretized with
/// mean-value weights measured on the 3D lens mesh. Returns n×2 positions in input-image pixels.
/// Throws volspline::Error if the sparse solve fails (degenerate lens mesh).
Eigen::MatrixX2d harmonic_texture(const LensMesh& lens);

}  // namespace volspline::lens
