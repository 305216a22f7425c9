// SPDX-License-Identifier: MIT
#include "core/lens/baseline_lens.h"

#include <algorithm>

namespace volspline::lens {

namespace {

// Output radius of an input point at radius r from the lens centre.
double radial_map(BaselineKind kind, const RadialLens& lens, double r, double s) {
  const double R = lens.lens_radius, F = lens.focus_radius;
  switch (kind) {
    case BaselineKind::Fisheye: {
      const double x = r / R, d = s - 1.0;  // Sarkar & Brown 1992, Cartesian form
      return R * (d + 1.0) * x / (d * x + 1.0);
    }
    case BaselineKind::Bifocal: {
      const double a = F / s;
      return r <= a ? s * r : F + (r - a) * (R - F) / (R - a);
    }
    case BaselineKind::Zoom:
      return r <= F / s ? s * r : F;  // r in [F/s, F) is covered by the inset
  }
  return r;
}

}  // namespace

Eigen::MatrixX2d baseline_positions(BaselineKind kind, const Eigen::MatrixX2d& texture,
                                    const std::vector<RadialLens>& lenses, double magnification) {
  Eigen::MatrixX2d out = texture;
  for (Eigen::Index v = 0; v < texture.rows(); ++v) {
    const Eigen::Vector2d p = texture.row(v).transpose();
    for (const RadialLens& lens : lenses) {
      const double reach = kind == BaselineKind::Zoom ? lens.focus_radius : lens.lens_radius;
      const Eigen::Vector2d d = p - lens.centre;
      const double r = d.norm();
      if (r >= reach) continue;
      if (r > 0) out.row(v) = (lens.centre + d * (radial_map(kind, lens, r, magnification) / r)).transpose();
      break;
    }
  }
  return out;
}

}  // namespace volspline::lens
