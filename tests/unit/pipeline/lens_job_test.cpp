// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/pipeline/lens_job.h"
#include "tests/unit/common/test_lenses.h"

using namespace volspline;
using namespace volspline::pipeline;
using volspline::test::checkerboard;

namespace {

Image circles(int w, int h) {
  Image img{w, h, 3, std::vector<std::uint8_t>(std::size_t(w) * h * 3)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        img.pixels[(y * w + x) * 3 + c] = (int(std::hypot(x - w / 2.0, y - h / 2.0) / 6) % 2) ? 200 : 40 + 30 * c;
  return img;
}

LensInput input_with(Image image, const std::vector<std::string>& rois) {
  LensInput in;
  in.image = std::move(image);
  for (const auto& r : rois) in.rois.push_back(lens::parse_roi_spec(r).roi);
  return in;
}

}  // namespace

TEST_CASE("metric lens: magnification at the centre within 10% of the request, far pixels unchanged") {
  const LensInput in = input_with(checkerboard(160, 160, 8), {"circle:80,80,30"});
  LensOptions o;
  o.grid = 48;
  const LensResult r = run_lens(in, o);
  CHECK(r.stats.magnification_center == doctest::Approx(2.0).epsilon(0.10));
  CHECK(r.stats.flipped_triangles == 0);
  CHECK(r.stats.converged);
  REQUIRE(r.image.pixels.size() == in.image.pixels.size());
  // Far outside the ROI and its context band (30·1.75 px) nothing moves: one grey level of rounding.
  for (int y = 0; y < 160; ++y)
    for (int x = 0; x < 160; ++x)
      if (std::hypot(x + 0.5 - 80, y + 0.5 - 80) > 30 * 1.75 + 8)
        CHECK(std::abs(int(r.image.at(x, y, 0)) - int(in.image.at(x, y, 0))) <= 1);
}

TEST_CASE("no folds for the thesis' alpha values with one to three ROIs") {
  const std::vector<std::vector<std::string>> roi_sets = {
      {"circle:60,60,20"}, {"circle:40,40,16", "rect:90,80,30,24"}, {"circle:30,30,14", "circle:90,40,14", "polygon:40,80,80,80,60,110"}};
  for (const auto& rois : roi_sets)
    for (double alpha : {0.0, 0.001, 0.01, 1.0}) {
      const LensInput in = input_with(circles(120, 120), rois);
      LensOptions o;
      o.grid = 32;
      o.alpha = alpha;
      o.height = 1.0;
      const LensResult r = run_lens(in, o);
      INFO("rois " << rois.size() << " alpha " << alpha);
      CHECK(r.stats.flipped_triangles == 0);
      CHECK(r.image.channels == 3);
    }
}

TEST_CASE("baselines run on the same grid and reach the requested magnification") {
  const LensInput in = input_with(checkerboard(120, 120, 6), {"circle:60,60,24"});
  for (LensMethod m : {LensMethod::Fisheye, LensMethod::Bifocal, LensMethod::Zoom}) {
    LensOptions o;
    o.grid = 40;
    o.method = m;
    const LensResult r = run_lens(in, o);
    CHECK(r.stats.magnification_center == doctest::Approx(2.0).epsilon(0.02));  // direct search on a closed form
    CHECK(r.stats.iterations == 0);
  }
}

TEST_CASE("square boundary keeps the output size and does not fold") {
  const LensInput in = input_with(checkerboard(100, 80, 5), {"circle:50,40,20"});
  LensOptions o;
  o.grid = 30;
  o.height = 1.0;
  o.boundary = LensBoundary::Square;
  const LensResult r = run_lens(in, o);
  CHECK(r.image.width == 100);
  CHECK(r.image.height == 80);
  CHECK(r.stats.flipped_triangles == 0);
}

TEST_CASE("bad options and inputs name the problem") {
  const LensInput in = input_with(checkerboard(64, 64, 4), {"circle:32,32,10"});
  const auto fails = [&](LensOptions o, const std::string& text) {
    CHECK_THROWS_WITH_AS(run_lens(in, o), doctest::Contains(text.c_str()), Error);
  };
  LensOptions o;
  o.magnification = 1.0;
  fails(o, "magnification must be > 1");
  o = {};
  o.magnification = 1000;
  fails(o, "at most 16");
  o = {};
  o.grid = 3;
  fails(o, "grid must be at least 4");
  o = {};
  o.alpha = 2;
  fails(o, "alpha must be in [0, 1]");
  o = {};
  o.band = 0;
  fails(o, "band must be in");
  o = {};
  o.height = 1;
  o.height_scale = {1.0, 1.0};
  fails(o, "`height_scale` needs one entry per ROI (1), got 2");
  o.height_scale = {0.0};
  fails(o, "`height_scale` entries must be in (0, 10]");
  CHECK_THROWS_WITH_AS(run_lens(input_with(checkerboard(64, 64, 4), {}), LensOptions{}), doctest::Contains("at least one ROI"), Error);
  CHECK_THROWS_WITH_AS(run_lens(input_with(checkerboard(64, 64, 4), {"circle:300,30,5"}), LensOptions{}),
                       doctest::Contains("outside the 64x64 image"), Error);
  CHECK_THROWS_WITH_AS(run_lens(input_with(Image{}, {"circle:3,3,1"}), LensOptions{}), doctest::Contains("malformed image"), Error);
}

TEST_CASE("focus distortion is part of the whole-image distortion") {
  const LensInput in = input_with(checkerboard(160, 160, 8), {"circle:80,80,30"});
  for (LensMethod m : {LensMethod::Metric, LensMethod::Fisheye, LensMethod::Bifocal}) {
    LensOptions o;
    o.grid = 40;
    o.method = m;
    o.render = pipeline::LensOptions::Render::Off;
    const LensStats s = run_lens(in, o).stats;
    CHECK(s.distortion_max_focus <= s.distortion_max);
    CHECK(s.distortion_sum_focus <= s.distortion_sum);
    CHECK(s.distortion_sum_focus > 0);  // a magnifying lens changes shapes somewhere in the focus
  }
}

TEST_CASE("metric lens: lower whole-image distortion_max than fisheye and bifocal at its measured magnification") {
  // The acceptance criterion on a small grid: same ROI, same free band, same magnification.
  const LensInput in = input_with(checkerboard(200, 200, 8), {"circle:100,90,30"});
  LensOptions o;
  o.grid = 60;
  o.render = pipeline::LensOptions::Render::Off;
  const LensStats metric = run_lens(in, o).stats;
  REQUIRE(metric.flipped_triangles == 0);
  for (LensMethod m : {LensMethod::Fisheye, LensMethod::Bifocal}) {
    LensOptions b = o;
    b.method = m;
    b.magnification = metric.magnification_center;
    const LensStats base = run_lens(in, b).stats;
    INFO("baseline " << int(m) << " max " << base.distortion_max << " metric " << metric.distortion_max);
    CHECK(base.magnification_center == doctest::Approx(metric.magnification_center).epsilon(0.02));
    CHECK(metric.distortion_max < base.distortion_max);
    CHECK(metric.distortion_sum < base.distortion_sum);
  }
}

TEST_CASE("metric lens: no exported triangle turned over against the texture at magnification 2 to 6") {
  const LensInput in = input_with(circles(200, 160), {"circle:100,80,30"});
  for (double m : {2.0, 3.0, 4.0, 6.0}) {
    LensOptions o;
    o.grid = 60;
    o.magnification = m;
    o.render = pipeline::LensOptions::Render::Off;
    const LensResult r = run_lens(in, o);
    INFO("magnification " << m << " reached " << r.stats.magnification_center);
    // Counted here as a viewer of the exported mesh sees it: every triangle, output area against
    // the texture area's sign.
    int turned = 0;
    for (Eigen::Index t = 0; t < r.triangles.rows(); ++t) {
      const auto area = [&](const Eigen::MatrixX2d& p) {
        const Eigen::Vector2d u = (p.row(r.triangles(t, 1)) - p.row(r.triangles(t, 0))).transpose();
        const Eigen::Vector2d v = (p.row(r.triangles(t, 2)) - p.row(r.triangles(t, 0))).transpose();
        return u.x() * v.y() - u.y() * v.x();
      };
      const double tex = area(r.texture), out = area(r.positions);
      if (tex != 0 && (tex > 0 ? out <= 0 : out >= 0)) ++turned;
    }
    CHECK(turned == 0);
    CHECK(r.stats.flipped_triangles == turned);
    CHECK(r.stats.magnification_requested == m);
    // Either the request is reached (within 3 %) or the result says it is limited.
    CHECK((r.stats.magnification_center >= 0.97 * m) != r.stats.magnification_limited);
  }
}

TEST_CASE("metric lens with a circle and a rectangle: each lens gets its own height, as close to the request as it goes") {
  // At one height the elongated rectangle (a ridge) magnifies less than the circle; the job scales
  // each lens's height, so the circle no longer overshoots and the rectangle comes closer.
  const LensInput in = input_with(circles(256, 256), {"circle:75,75,30", "rect:143,152,64,45"});
  LensOptions o;
  o.grid = 50;
  o.render = pipeline::LensOptions::Render::Off;
  const LensResult r = run_lens(in, o);
  const LensStats& s = r.stats;
  REQUIRE(s.height_scale_per_roi.size() == 2);
  REQUIRE(s.magnification_per_roi.size() == 2);
  INFO("magnification per ROI " << s.magnification_per_roi[0] << ", " << s.magnification_per_roi[1] << "; height scales "
                                << s.height_scale_per_roi[0] << ", " << s.height_scale_per_roi[1] << "; h0 " << s.height);
  CHECK(s.flipped_triangles == 0);
  CHECK(s.height_scale_per_roi[1] == 1.0);  // the rectangle is the taller lens
  CHECK(s.height_scale_per_roi[0] < 0.95);
  // Both lenses at the rectangle's height (the calibration's h0 shared, as before per-ROI heights):
  // the farthest lens lies farther from the request.
  LensOptions same = o;
  same.height = s.height;
  const LensStats t = run_lens(in, same).stats;
  const auto worst = [](const LensStats& x) {
    double w = 0;
    for (double m : x.magnification_per_roi) w = std::max(w, std::abs(std::log(m / 2.0)));
    return w;
  };
  CHECK(worst(s) < worst(t));
  CHECK(std::abs(std::log(s.magnification_per_roi[0] / 2.0)) < 0.05);
  // The height and the scales reported reproduce the run (what the page sends while dragging).
  LensOptions again = o;
  again.height = s.height;
  again.height_scale = s.height_scale_per_roi;
  const LensResult r2 = run_lens(in, again);
  CHECK((r2.positions.array() == r.positions.array()).all());
  CHECK(r2.stats.magnification_per_roi == s.magnification_per_roi);
  // One ROI: no scaling.
  const LensStats one = run_lens(input_with(circles(256, 256), {"circle:75,75,30"}), o).stats;
  CHECK(one.height_scale_per_roi == std::vector<double>{1.0});
}
