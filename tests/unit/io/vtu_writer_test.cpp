// SPDX-License-Identifier: MIT
#include "core/io/vtu_writer.h"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "tests/unit/io/appended_array.h"

#include "core/spline/bspline_volume.h"

using namespace volspline;

TEST_CASE("vtu of the identity spline: counts, hex order and unit scaled Jacobians") {
  const std::vector<double> knots = spline::boundary_restricted_knots({0.0, 1.0});
  Eigen::MatrixXd points(64, 3);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) points.row(i + 4 * (j + 4 * k)) << i / 3.0, j / 3.0, k / 3.0;  // Greville: identity
  const spline::TSpline ts = spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points));
  const std::string vtu = io::serialize_spline_vtu(ts, {2, 3, 4}, false);
  CHECK(vtu.find("NumberOfPoints=\"60\" NumberOfCells=\"24\"") != std::string::npos);
  CHECK(vtu.find("Name=\"scaled_jacobian\"") != std::string::npos);
  // First hex in VTK order: (0,0,0) (1,0,0) (1,1,0) (0,1,0) then the top face.
  const std::vector<std::int64_t> connectivity = test::appended_array<std::int64_t>(vtu, "connectivity");
  REQUIRE(connectivity.size() == 24 * 8);
  CHECK(std::vector<std::int64_t>(connectivity.begin(), connectivity.begin() + 8) ==
        std::vector<std::int64_t>{0, 1, 4, 3, 12, 13, 16, 15});
  const std::vector<double> quality = test::appended_array<double>(vtu, "scaled_jacobian");
  REQUIRE(quality.size() == 24);
  CHECK(quality[0] == doctest::Approx(1.0));
}
