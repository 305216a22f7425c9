// SPDX-License-Identifier: MIT
#include "core/lens/baseline_lens.h"

#include <doctest/doctest.h>

#include <cmath>
#include <utility>
#include <vector>

using namespace volspline;

namespace {

// Output radius (from the lens centre) of the input point at radius r along direction angle_rad.
double output_radius(lens::BaselineKind kind, const lens::RadialLens& l, double r, double m, double angle_rad = 0.3) {
  Eigen::MatrixX2d p(1, 2);
  p << l.centre.x() + r * std::cos(angle_rad), l.centre.y() + r * std::sin(angle_rad);
  const Eigen::Vector2d out = lens::baseline_positions(kind, p, {l}, m).row(0).transpose();
  // Radial: the direction is kept.
  const Eigen::Vector2d d = out - l.centre;
  if (r > 0) CHECK(std::abs(d.x() * std::sin(angle_rad) - d.y() * std::cos(angle_rad)) < 1e-12 * (1 + d.norm()));
  return d.norm();
}

lens::RadialLens test_lens() {
  lens::RadialLens l;
  l.centre = Eigen::Vector2d(50, 40);
  l.focus_radius = 10;
  l.lens_radius = 30;
  return l;
}

// Each pair: input radius → expected output radius (exact up to rounding).
void check_radii(lens::BaselineKind kind, double m, const std::vector<std::pair<double, double>>& radii) {
  const lens::RadialLens l = test_lens();
  for (const auto& pair : radii) {  // no structured binding: CAPTURE's lambda cannot name one in C++17
    const double in = pair.first, out = pair.second;
    CAPTURE(in);
    CHECK(output_radius(kind, l, in, m) == doctest::Approx(out).epsilon(1e-14));
  }
}

}  // namespace

TEST_CASE("fisheye: Sarkar–Brown G(x) = (d+1)x / (dx+1) on the lens radius") {
  // m = 3 (d = 2), lens radius 30: x = 0.5 → 3·0.5 / 2 = 0.75; x = 0.1 → 0.3 / 1.2 = 0.25; the
  // lens radius and beyond do not move.
  check_radii(lens::BaselineKind::Fisheye, 3.0, {{0.0, 0.0}, {15.0, 22.5}, {3.0, 7.5}, {30.0, 30.0}, {45.0, 45.0}});
  // Magnification at the centre: G'(0) = d + 1.
  CHECK(output_radius(lens::BaselineKind::Fisheye, test_lens(), 1e-6, 3.0) / 1e-6 == doctest::Approx(3.0).epsilon(1e-5));
}

TEST_CASE("bifocal: uniform magnification in the focus, linear compression out to the lens radius") {
  // m = 2.5, focus radius 10: the focus holds the input disc of radius 4; the transition maps
  // [4, 30] linearly onto [10, 30] (its middle 17 → 20).
  check_radii(lens::BaselineKind::Bifocal, 2.5, {{2.0, 5.0}, {4.0, 10.0}, {17.0, 20.0}, {30.0, 30.0}, {31.0, 31.0}});
}

TEST_CASE("zoom: a magnified inset over the focus disc, its rim hides the input beneath") {
  // m = 2: input within 5 is doubled; input in [5, 10) lies under the inset (pushed to its rim);
  // from the focus radius on nothing moves (the lens radius plays no part).
  check_radii(lens::BaselineKind::Zoom, 2.0, {{3.0, 6.0}, {5.0, 10.0}, {7.0, 10.0}, {10.0, 10.0}, {20.0, 20.0}});
}

TEST_CASE("baseline lenses: a point inside two lenses follows the first; the centre stays") {
  lens::RadialLens a = test_lens(), b = test_lens();
  b.centre = Eigen::Vector2d(70, 40);  // overlaps a between x = 40 and 80
  Eigen::MatrixX2d p(3, 2);
  p << 60, 40,  // 10 from both centres
      50, 40,   // a's centre
      200, 200; // outside both
  const Eigen::MatrixX2d both = lens::baseline_positions(lens::BaselineKind::Fisheye, p, {a, b}, 2.0);
  const Eigen::MatrixX2d first = lens::baseline_positions(lens::BaselineKind::Fisheye, p, {a}, 2.0);
  CHECK(both.row(0) == first.row(0));
  CHECK(both(0, 0) > 60.0);  // pushed away from a's centre, towards b's
  CHECK(both.row(1) == p.row(1));
  CHECK(both.row(2) == p.row(2));
}
