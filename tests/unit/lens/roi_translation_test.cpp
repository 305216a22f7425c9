// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/lens/roi_translation.h"

using namespace volspline;
using namespace volspline::lens;

namespace {

Roi roi(const std::string& text) { return parse_roi_spec(text).roi; }

}  // namespace

TEST_CASE("roi_translation: one common offset of equal shapes") {
  const auto d = roi_translation({roi("circle:10,20,5"), roi("rect:30,40,8,6")},
                                 {roi("circle:13.5,18,5"), roi("rect:33.5,38,8,6")});
  REQUIRE(d.has_value());
  CHECK(d->x() == 3.5);
  CHECK(d->y() == -2.0);
  const auto poly = roi_translation({roi("polygon:0,0,10,0,5,8")}, {roi("polygon:1,2,11,2,6,10")});
  REQUIRE(poly.has_value());
  CHECK(poly->x() == 1.0);
  CHECK(poly->y() == 2.0);
  const auto same = roi_translation({roi("circle:10,20,5")}, {roi("circle:10,20,5")});
  REQUIRE(same.has_value());
  CHECK(same->norm() == 0.0);
}

TEST_CASE("roi_translation: resized, reshaped, unequal offsets, counts and masks do not match") {
  CHECK_FALSE(roi_translation({roi("circle:10,20,5")}, {roi("circle:12,20,6")}));
  CHECK_FALSE(roi_translation({roi("rect:30,40,8,6")}, {roi("rect:31,40,8,7")}));
  CHECK_FALSE(roi_translation({roi("circle:10,20,5")}, {roi("rect:10,20,5,5")}));
  CHECK_FALSE(roi_translation({roi("circle:10,20,5"), roi("circle:40,20,5")}, {roi("circle:11,20,5"), roi("circle:42,20,5")}));
  CHECK_FALSE(roi_translation({roi("polygon:0,0,10,0,5,8")}, {roi("polygon:1,2,11,2,6,11")}));
  CHECK_FALSE(roi_translation({roi("circle:10,20,5")}, {roi("circle:10,20,5"), roi("circle:30,20,5")}));
  CHECK_FALSE(roi_translation({}, {}));
  Roi mask;
  mask.shape = RoiShape::Mask;
  CHECK_FALSE(roi_translation({mask}, {mask}));
}

TEST_CASE("roi_reach_box: bounding box widened by the reach") {
  const PixelBox c = roi_reach_box(roi("circle:10,20,5"), 2);
  CHECK(c.x0 == 3.0);
  CHECK(c.y0 == 13.0);
  CHECK(c.x1 == 17.0);
  CHECK(c.y1 == 27.0);
  const PixelBox r = roi_reach_box(roi("rect:30,40,8,6"), 1);
  CHECK(r.x0 == 29.0);
  CHECK(r.y0 == 39.0);
  CHECK(r.x1 == 39.0);
  CHECK(r.y1 == 47.0);
  const PixelBox p = roi_reach_box(roi("polygon:0,0,10,0,5,8"), 0.5);
  CHECK(p.x0 == -0.5);
  CHECK(p.y0 == -0.5);
  CHECK(p.x1 == 10.5);
  CHECK(p.y1 == 8.5);
}
