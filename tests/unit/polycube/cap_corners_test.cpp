// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <set>
#include <vector>

#include "core/polycube/cap_corners.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

// An open cap of revolution around z: rings of 48 vertices along the profile (z, r)(s) for the
// arc length s in [0, length], the last ring replaced by the apex when r ends at 0. Height per
// vertex: its arc length s along the meridian (the distance from the rim, exactly).
struct Cap {
  mesh::TriangleMesh mesh;
  std::vector<double> height;
  double length = 0.0;
};

Cap revolve(const std::function<Eigen::Vector2d(double)>& profile, double length, int rings) {
  const int n = 48;
  const double pi = 3.14159265358979323846;
  std::vector<double> xyz;
  Cap cap;
  cap.length = length;
  for (int k = 0; k < rings; ++k) {
    const double s = length * k / rings;
    const Eigen::Vector2d zr = profile(s);
    for (int i = 0; i < n; ++i) {
      xyz.insert(xyz.end(), {zr(1) * std::cos(2 * pi * i / n), zr(1) * std::sin(2 * pi * i / n), zr(0)});
      cap.height.push_back(s);
    }
  }
  const Eigen::Vector2d apex = profile(length);
  xyz.insert(xyz.end(), {0.0, 0.0, apex(0)});
  cap.height.push_back(length);
  std::vector<int> faces;
  for (int k = 0; k + 1 < rings; ++k)
    for (int i = 0; i < n; ++i) {
      const int a = k * n + i, b = k * n + (i + 1) % n, c = (k + 1) * n + (i + 1) % n, d = (k + 1) * n + i;
      faces.insert(faces.end(), {a, b, c, a, c, d});
    }
  const int top = rings * n;
  for (int i = 0; i < n; ++i) faces.insert(faces.end(), {(rings - 1) * n + i, (rings - 1) * n + (i + 1) % n, top});
  cap.mesh = test::make_mesh(xyz, faces);
  return cap;
}

constexpr double kPi = 3.14159265358979323846;

}  // namespace

TEST_CASE("cap corners: a round cap keeps its end face halfway up, a limb's starts near its tip") {
  // Hemisphere of radius 1 from its equator.
  const Cap hemisphere = revolve([](double s) { return Eigen::Vector2d(std::sin(s), std::cos(s)); }, kPi / 2, 40);
  CHECK(polycube::cap_corner_level(hemisphere.mesh, hemisphere.height, hemisphere.length) == doctest::Approx(0.5));
  // Capsule: a cylinder of radius 1 and length 4, then its round end.
  const Cap capsule = revolve(
      [](double s) {
        return s <= 4.0 ? Eigen::Vector2d(s, 1.0) : Eigen::Vector2d(4.0 + std::sin(s - 4.0), std::cos(s - 4.0));
      },
      4.0 + kPi / 2, 120);
  const double lambda = polycube::cap_corner_level(capsule.mesh, capsule.height, capsule.length);
  MESSAGE("capsule: end face from " << lambda * capsule.length);
  CHECK(lambda * capsule.length >= 3.5);
  CHECK(lambda * capsule.length <= 4.2);  // about the start of the round end
  // A cone of half-angle 5° never gets as wide as it is long: two mean edges below its apex.
  const double tan5 = std::tan(5.0 * kPi / 180.0);
  const Cap cone = revolve([&](double s) { return Eigen::Vector2d(s, tan5 * (10.0 - s)); }, 10.0, 40);
  CHECK(polycube::cap_corner_level(cone.mesh, cone.height, cone.length) >= 0.9);
  // The level set of the capsule's height at 2 is its 48-gon of radius 1.
  CHECK(polycube::level_set_length(capsule.mesh, capsule.height, 2.01) == doctest::Approx(96.0 * std::sin(kPi / 48)).epsilon(1e-9));
}

TEST_CASE("cap corners: front corners follow the loop corners' angles around the limb") {
  const Cap capsule = revolve(
      [](double s) {
        return s <= 4.0 ? Eigen::Vector2d(s, 1.0) : Eigen::Vector2d(4.0 + std::sin(s - 4.0), std::cos(s - 4.0));
      },
      4.0 + kPi / 2, 120);
  // Loop corners at 10°, 100°, 190°, 280° on the rim.
  std::array<Eigen::Vector3d, 4> below;
  for (int i = 0; i < 4; ++i) {
    const double a = (10.0 + 90.0 * i) * kPi / 180.0;
    below[i] = Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
  }
  const std::array<int, 4> c =
      polycube::front_corners(capsule.mesh, capsule.height, 3.0, Eigen::Vector3d(0.0, 0.0, 5.0), below);
  std::set<int> distinct(c.begin(), c.end());
  CHECK(distinct.size() == 4);
  for (int i = 0; i < 4; ++i) {
    REQUIRE(c[i] >= 0);
    const Eigen::Vector3d x = capsule.mesh.positions.row(c[i]).transpose();
    CHECK(capsule.height[c[i]] >= 3.0);
    CHECK(capsule.height[c[i]] < 3.0 + 0.05);  // on the front: one ring up at most
    // Within half a ring step (7.5° / 2) of the loop corner's angle.
    const double d = std::abs(std::remainder(std::atan2(x(1), x(0)) - std::atan2(below[i](1), below[i](0)), 2 * kPi));
    CHECK(d <= 3.75 * kPi / 180.0 + 1e-9);
  }
}
