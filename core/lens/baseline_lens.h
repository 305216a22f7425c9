// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>

namespace volspline::lens {

/// Classical lenses that the metric lens is compared with (§6.5, Table 6.1).
enum class BaselineKind {
  Fisheye,  ///< Sarkar–Brown graphical fisheye G(x) = (d+1)x / (dx+1), smooth, magnification d+1 at the centre
  Bifocal,  ///< piecewise linear in the radius: uniform focus, linear compression in the transition
  Zoom,     ///< magnified inset over the focus disc, the input under its rim hidden
};

/// One radial lens in input-image pixels.
struct RadialLens {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double focus_radius = 0;  ///< output radius of the magnified focus (bifocal, zoom)
  double lens_radius = 0;   ///< radius beyond which nothing moves (fisheye, bifocal); > focus_radius
};

/// Output positions of the points `texture` (n×2, pixels) under the baseline lens with the given
/// magnification at the centre (> 1). A point inside several lenses follows the first.
Eigen::MatrixX2d baseline_positions(BaselineKind kind, const Eigen::MatrixX2d& texture,
                                    const std::vector<RadialLens>& lenses, double magnification);

}  // namespace volspline::lens
