// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/pipeline/lens_job.h"
#include "core/pipeline/lens_session.h"

using namespace volspline;
using namespace volspline::pipeline;

namespace {

Image rings(int w, int h) {
  Image img{w, h, 1, std::vector<std::uint8_t>(std::size_t(w) * h)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.pixels[y * w + x] = (int(std::hypot(x - w / 2.0, y - h / 2.0) / 5) % 2) ? 210 : 30;
  return img;
}

LensInput input_with(const std::vector<std::string>& rois) {
  LensInput in;
  in.image = rings(96, 80);
  for (const auto& r : rois) in.rois.push_back(lens::parse_roi_spec(r).roi);
  return in;
}

LensOptions small(double alpha = 0.0) {
  LensOptions o;
  o.grid = 28;  // small: the whole file stays fast under the sanitizers
  o.alpha = alpha;
  o.render = pipeline::LensOptions::Render::Off;
  return o;
}

// Bit for bit: positions, texture, triangles and every non-timing stat.
void check_identical(const LensResult& a, const LensResult& b) {
  REQUIRE(a.positions.rows() == b.positions.rows());
  CHECK((a.positions.array() == b.positions.array()).all());
  CHECK((a.texture.array() == b.texture.array()).all());
  CHECK((a.triangles.array() == b.triangles.array()).all());
  CHECK(a.image.pixels == b.image.pixels);
  const LensStats &s = a.stats, &t = b.stats;
  CHECK(s.distortion_sum == t.distortion_sum);
  CHECK(s.distortion_max == t.distortion_max);
  CHECK(s.distortion_sum_focus == t.distortion_sum_focus);
  CHECK(s.distortion_max_focus == t.distortion_max_focus);
  CHECK(s.magnification_center == t.magnification_center);
  CHECK(s.magnification_per_roi == t.magnification_per_roi);
  CHECK(s.flipped_triangles == t.flipped_triangles);
  CHECK(s.iterations == t.iterations);
  CHECK(s.converged == t.converged);
  CHECK(s.height == t.height);
  CHECK(s.baseline_parameter == t.baseline_parameter);
  CHECK(s.vertices == t.vertices);
  CHECK(s.triangles == t.triangles);
}

}  // namespace

TEST_CASE("session: alpha changes at a given height re-run only the iterations, identical to run_lens") {
  const LensInput in = input_with({"circle:48,40,14"});
  LensSession session;
  LensOptions o = small();
  o.height = 1.1;
  int builds = -1;
  for (double alpha : {0.0, 0.5, 1.0, 0.0}) {
    o.alpha = alpha;
    CAPTURE(alpha);
    const LensResult live = session.run(in, o);
    check_identical(live, run_lens(in, o));
    if (builds < 0) {
      builds = session.counters().mesh_builds;  // the first run builds the final-grid mesh once
      CHECK(builds == 1);
      CHECK(live.stats.ms_factorize > 0);
    } else {
      CHECK(session.counters().mesh_builds == builds);  // α only changes the metric, not W
      CHECK(live.stats.ms_factorize == 0);
      CHECK(live.stats.ms_mesh == 0);
    }
  }
  CHECK(session.counters().mesh_reuses == 3);
  CHECK(session.counters().runs == 4);
}

TEST_CASE("session: a repeated calibrated request reuses h0 and the mesh, identical to run_lens") {
  const LensInput in = input_with({"circle:48,40,14"});
  LensSession session;
  const LensOptions o = small(0.25);
  const LensResult first = session.run(in, o);
  const LensResult reference = run_lens(in, o);
  check_identical(first, reference);
  CHECK(session.counters().calibrations == 1);
  const int builds = session.counters().mesh_builds;
  CHECK(builds >= 2);  // the coarse secant visits at least two heights
  const LensResult again = session.run(in, o);
  check_identical(again, reference);
  CHECK(session.counters().calibration_reuses == 1);
  CHECK(session.counters().mesh_builds == builds);
  CHECK(again.stats.ms_calibration == 0);
  // Rendering is not part of the cache key: the same request with an image.
  LensOptions rendered = o;
  rendered.render = pipeline::LensOptions::Render::On;
  check_identical(session.run(in, rendered), run_lens(in, rendered));
  CHECK(session.counters().mesh_builds == builds);
}

TEST_CASE("session: a changed ROI, magnification, grid or boundary rebuilds and still matches run_lens") {
  LensSession session;
  LensInput in = input_with({"circle:48,40,14"});
  LensOptions o = small();
  check_identical(session.run(in, o), run_lens(in, o));
  int builds = session.counters().mesh_builds;
  const auto rebuilt = [&](const LensInput& input, const LensOptions& options) {
    check_identical(session.run(input, options), run_lens(input, options));
    const bool more = session.counters().mesh_builds > builds;
    builds = session.counters().mesh_builds;
    return more;
  };
  in.rois[0].values = {52, 40, 14};  // dragged
  CHECK(rebuilt(in, o));
  in.rois[0].values = {52, 40, 17};  // resized
  CHECK(rebuilt(in, o));
  o.magnification = 2.6;
  CHECK(rebuilt(in, o));
  o.grid = 24;
  CHECK(rebuilt(in, o));
  o.boundary = LensBoundary::Square;
  CHECK(rebuilt(in, o));
  const LensInput two = input_with({"circle:30,30,10", "rect:60,40,20,16"});
  CHECK(rebuilt(two, o));
  // Baselines never touch the metric caches.
  LensOptions fisheye = small();
  fisheye.method = LensMethod::Fisheye;
  CHECK_FALSE(rebuilt(in, fisheye));
}

TEST_CASE("session: the mesh cache stays bounded and a cleared session still matches run_lens") {
  LensSession session;
  const LensInput in = input_with({"circle:48,40,14"});
  LensOptions o = small();
  for (int k = 0; k < 12; ++k) {
    o.height = 0.5 + 0.1 * k;  // twelve different meshes: older ones are evicted
    session.run(in, o);
  }
  o.height = 0.5;  // the oldest: evicted, so built again
  const int builds = session.counters().mesh_builds;
  check_identical(session.run(in, o), run_lens(in, o));
  CHECK(session.counters().mesh_builds == builds + 1);
  session.clear();
  check_identical(session.run(in, o), run_lens(in, o));
  CHECK(session.counters().mesh_builds == builds + 2);
}

TEST_CASE("session: errors and cancellation leave the session usable") {
  LensSession session;
  const LensInput in = input_with({"circle:48,40,14"});
  LensOptions bad = small();
  bad.alpha = 2.0;
  CHECK_THROWS_WITH_AS(session.run(in, bad), doctest::Contains("alpha must be in [0, 1]"), Error);
  const LensInput outside = input_with({"circle:500,40,14"});
  CHECK_THROWS_AS(session.run(outside, small()), Error);
  LensOptions o = small();
  o.height = 1.0;
  const Progress stop([](const std::string& stage, double) { return stage != "flatten"; });
  CHECK_THROWS_AS(session.run(in, o, stop), Cancelled);
  CHECK(session.counters().runs == 0);
  check_identical(session.run(in, o), run_lens(in, o));  // the mesh built before the cancel is reused
  CHECK(session.counters().mesh_builds == 1);
  CHECK(session.counters().mesh_reuses == 1);
}

TEST_CASE("session: live drags translate the last solved run; full runs stay identical to run_lens") {
  LensSession session;
  LensInput in = input_with({"circle:48,40,14"});
  LensOptions full = small();
  full.height = 1.1;
  LensOptions live = full;
  live.mode = LensMode::Live;

  // No solved run yet: a live request is solved in full (and becomes the base).
  const LensResult base = session.run(in, live);
  CHECK_FALSE(base.stats.translated);
  check_identical(base, run_lens(in, full));
  const int builds = session.counters().mesh_builds;

  // Moved: the base deformation moved by the offset, nothing solved.
  in.rois[0].values = {52, 43, 14};
  const LensResult moved = session.run(in, live);
  CHECK(moved.stats.translated);
  CHECK(session.counters().translation_reuses == 1);
  CHECK(session.counters().mesh_builds == builds);
  REQUIRE(moved.positions.rows() == base.positions.rows());
  const Eigen::RowVector2d offset(4, 3);
  CHECK(((moved.positions.rowwise() - offset) - base.positions).cwiseAbs().maxCoeff() <= 1e-12);
  CHECK(((moved.texture.rowwise() - offset) - base.texture).cwiseAbs().maxCoeff() <= 1e-12);
  CHECK((moved.triangles.array() == base.triangles.array()).all());
  CHECK(moved.stats.magnification_center == base.stats.magnification_center);
  CHECK(moved.stats.height == base.stats.height);

  // The full run at the new place (what the page runs on release) is the one-shot job, and the
  // preview is close to it: only the grid's sampling of the lens differs.
  const LensResult solved = session.run(in, full);
  CHECK_FALSE(solved.stats.translated);
  check_identical(solved, run_lens(in, full));
  CHECK(moved.stats.magnification_center == doctest::Approx(solved.stats.magnification_center).epsilon(0.05));

  // A live request rendered: far from the lens the image is the input (uncovered pixels too).
  in.rois[0].values = {46, 38, 14};
  LensOptions rendered = live;
  rendered.render = pipeline::LensOptions::Render::On;
  const LensResult image = session.run(in, rendered);
  CHECK(image.stats.translated);
  REQUIRE(image.image.pixels.size() == in.image.pixels.size());
  for (int p : {0, 95, 80 * 96 - 1, 79 * 96}) CHECK(image.image.pixels[p] == in.image.pixels[p]);

  // Resized, near the border, another α or the square boundary: solved in full, identical to run_lens.
  const auto solved_in_full = [&](const LensInput& input, const LensOptions& options) {
    const LensResult r = session.run(input, options);
    LensOptions reference = options;
    reference.mode = LensMode::Full;
    check_identical(r, run_lens(input, reference));
    return !r.stats.translated;
  };
  in.rois[0].values = {46, 38, 15};
  CHECK(solved_in_full(in, live));
  in.rois[0].values = {20, 38, 15};
  CHECK(solved_in_full(in, live));
  in.rois[0].values = {46, 38, 15};
  LensOptions other = live;
  other.alpha = 0.5;
  CHECK(solved_in_full(in, other));
  other.boundary = LensBoundary::Square;
  CHECK(solved_in_full(in, other));
  CHECK(session.counters().translation_reuses == 2);
}
