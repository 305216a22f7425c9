// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>

#include "core/lens/roi_field.h"

using namespace volspline::lens;

TEST_CASE("circle field is exact: d = r/R, outside distance r − R") {
  const RoiField f = RoiField::build(parse_roi_spec("circle:50,40,20").roi, 100, 100, 1.0);
  CHECK(f.axis_distance(50, 40) == doctest::Approx(0.0).epsilon(1e-12));
  CHECK(f.axis_distance(60, 40) == doctest::Approx(0.5).epsilon(1e-12));
  CHECK(f.axis_distance(90, 40) == 1.0);
  CHECK(f.outside_distance(80, 40) == doctest::Approx(10.0).epsilon(1e-12));
  CHECK(f.inscribed_radius() == 20.0);
}

TEST_CASE("rasterized rect: centre, inscribed radius, axis distance grows to the boundary") {
  const RoiField f = RoiField::build(parse_roi_spec("rect:20,30,60,40").roi, 100, 100, 1.0);
  // One-pixel raster: positions and radii within a pixel.
  CHECK(f.centre().y() == doctest::Approx(50.0).epsilon(0.03));
  CHECK(f.inscribed_radius() == doctest::Approx(20.0).epsilon(0.05));
  CHECK(f.axis_distance(50, 50) < 0.1);
  CHECK(f.axis_distance(50, 40) == doctest::Approx(0.5).epsilon(0.1));
  CHECK(f.axis_distance(50, 29) == 1.0);
  CHECK(f.outside_distance(50, 20) == doctest::Approx(10.0).epsilon(0.1));
  CHECK(f.equivalent_radius() == doctest::Approx(std::sqrt(2400 / M_PI)).epsilon(0.02));
}

TEST_CASE("polygon and mask of the same square agree") {
  const RoiField p = RoiField::build(parse_roi_spec("polygon:20,20,60,20,60,60,20,60").roi, 80, 80, 1.0);
  Roi mask = parse_roi_spec("mask:x").roi;
  mask.mask = Image{80, 80, 1, std::vector<std::uint8_t>(6400, 0)};
  for (int y = 20; y < 60; ++y)
    for (int x = 20; x < 60; ++x) mask.mask.pixels[y * 80 + x] = 255;
  const RoiField m = RoiField::build(mask, 80, 80, 1.0);
  for (double x : {25.0, 33.0, 40.0, 47.0})
    CHECK(p.axis_distance(x, 37) == doctest::Approx(m.axis_distance(x, 37)).epsilon(1e-9));
}
