// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/lens/roi.h"

using namespace volspline;
using namespace volspline::lens;

TEST_CASE("parse_roi_spec reads every kind") {
  const RoiSpec c = parse_roi_spec("circle:10,20,5");
  CHECK(c.roi.shape == RoiShape::Circle);
  CHECK(c.roi.values == std::vector<double>{10, 20, 5});
  CHECK(parse_roi_spec("rect:1,2,3,4").roi.shape == RoiShape::Rect);
  CHECK(parse_roi_spec("polygon:0,0,10,0,0,10").roi.values.size() == 6);
  const RoiSpec m = parse_roi_spec("mask:a/b.png");
  CHECK(m.roi.shape == RoiShape::Mask);
  CHECK(m.mask_path == "a/b.png");
}

TEST_CASE("parse_roi_spec names the problem") {
  CHECK_THROWS_WITH_AS(parse_roi_spec("blob:1,2"), doctest::Contains("unknown kind 'blob'"), Error);
  CHECK_THROWS_WITH_AS(parse_roi_spec("circle:1,2"), doctest::Contains("circle needs 3 numbers"), Error);
  CHECK_THROWS_WITH_AS(parse_roi_spec("circle:1,x,3"), doctest::Contains("'x' is not a number"), Error);
  CHECK_THROWS_WITH_AS(parse_roi_spec("polygon:0,0,1,1"), doctest::Contains("at least 3 points"), Error);
  CHECK_THROWS_WITH_AS(parse_roi_spec("circle"), doctest::Contains("expected circle:"), Error);
  CHECK_THROWS_WITH_AS(parse_roi_spec("mask:"), doctest::Contains("needs a file"), Error);
}

TEST_CASE("validate_roi rejects bad regions") {
  CHECK_NOTHROW(validate_roi(parse_roi_spec("circle:50,50,10").roi, 100, 100));
  CHECK_THROWS_WITH_AS(validate_roi(parse_roi_spec("circle:50,50,0").roi, 100, 100),
                       doctest::Contains("radius must be positive"), Error);
  CHECK_THROWS_WITH_AS(validate_roi(parse_roi_spec("circle:50,50,-3").roi, 100, 100),
                       doctest::Contains("radius must be positive"), Error);
  CHECK_THROWS_WITH_AS(validate_roi(parse_roi_spec("circle:500,50,10").roi, 100, 100),
                       doctest::Contains("outside the 100x100 image"), Error);
  CHECK_THROWS_WITH_AS(validate_roi(parse_roi_spec("rect:10,10,0,5").roi, 100, 100),
                       doctest::Contains("must be positive"), Error);
  CHECK_THROWS_WITH_AS(validate_roi(parse_roi_spec("polygon:0,0,10,10,20,20").roi, 100, 100),
                       doctest::Contains("zero area"), Error);
  Roi mask = parse_roi_spec("mask:m.png").roi;
  mask.mask = Image{10, 10, 1, std::vector<std::uint8_t>(100, 0)};
  CHECK_THROWS_WITH_AS(validate_roi(mask, 20, 20), doctest::Contains("mask is 10x10 but the image is 20x20"), Error);
  CHECK_THROWS_WITH_AS(validate_roi(mask, 10, 10), doctest::Contains("no inside pixel"), Error);
}
