// SPDX-License-Identifier: MIT
#include "core/io/vtu_writer.h"

#include <doctest/doctest.h>

#include "core/spline/bspline_volume.h"

using namespace volspline;

TEST_CASE("vtu of the identity spline: counts, hex order and unit scaled Jacobians") {
  const std::vector<double> knots = spline::boundary_restricted_knots({0.0, 1.0});
  Eigen::MatrixXd points(64, 3);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) points.row(i + 4 * (j + 4 * k)) << i / 3.0, j / 3.0, k / 3.0;  // Greville: identity
  const spline::TSpline ts = spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points));
  const std::string vtu = io::serialize_spline_vtu(ts, {2, 3, 4});
  CHECK(vtu.find("NumberOfPoints=\"60\" NumberOfCells=\"24\"") != std::string::npos);
  CHECK(vtu.find("Name=\"scaled_jacobian\"") != std::string::npos);
  // First hex in VTK order: (0,0,0) (1,0,0) (1,1,0) (0,1,0) then the top face.
  CHECK(vtu.find("0 1 4 3 12 13 16 15\n") != std::string::npos);
  const auto begin = vtu.find("format=\"ascii\">\n", vtu.find("Name=\"scaled_jacobian\"")) + 16;
  CHECK(vtu.substr(begin, 2) == "1\n");
}
