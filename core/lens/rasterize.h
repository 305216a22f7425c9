// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/common/image.h"
#include "core/mesh/triangle_mesh.h"

namespace volspline::lens {

/// Renders a flattened textured mesh (§6.2 step 3 output) into a width × height image with the
/// channels of `texture_image`. Each output pixel centre inside an output triangle takes the
/// barycentric blend of the triangle's texture coordinates and samples the input bilinearly there.
/// Coverage uses exact integer edge functions (1/256 pixel) with the top-left rule, so triangles
/// sharing an edge leave no gap and draw no pixel twice. Pixels covered by no triangle with positive
/// area sample the input at their own position.
/// output: n×2 pixel positions in the output; texture: n×2 pixel positions in the input image.
/// draw_count: if not null, receives width·height counts of the triangles that drew each pixel.
Image render_textured_mesh(const Image& texture_image, const Eigen::MatrixX2d& output,
                           const Eigen::MatrixX2d& texture, const mesh::Triangles& triangles, int width, int height,
                           std::vector<int>* draw_count = nullptr);

}  // namespace volspline::lens
