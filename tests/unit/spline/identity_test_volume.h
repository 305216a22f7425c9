// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/spline/bspline_volume.h"
#include "core/spline/tspline.h"
#include "core/spline/tspline_fitting.h"

namespace volspline::test {

/// The identity map of [0,1]³ as a uniform boundary-restricted cubic B-spline with 4 cells per
/// axis (control points at the Greville abscissae, 7³ of them), as a T-spline: the valid start
/// that the fold-repair tests fold on purpose.
inline spline::TSpline identity_test_volume() {
  const std::vector<double> knots = spline::boundary_restricted_knots({0.0, 0.25, 0.5, 0.75, 1.0});
  const int n = 7;
  Eigen::MatrixXd points(n * n * n, 3);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int idx[3] = {i, j, k};
        for (int a = 0; a < 3; ++a)
          points(i + n * (j + n * k), a) = (knots[idx[a] + 1] + knots[idx[a] + 2] + knots[idx[a] + 3]) / 3.0;
      }
  return spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points));
}

}  // namespace volspline::test
