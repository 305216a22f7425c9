// SPDX-License-Identifier: MIT
#include "core/param/surface_distance.h"

#include <limits>
#include <random>

#include <doctest/doctest.h>

#include "tests/unit/common/test_meshes.h"

using namespace volspline;

TEST_CASE("closest point on a triangle: regions") {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK((param::closest_point_on_triangle({0.2, 0.2, 5}, a, b, c) - Eigen::Vector3d(0.2, 0.2, 0)).norm() < 1e-15);
  CHECK((param::closest_point_on_triangle({-1, -1, 0}, a, b, c) - a).norm() < 1e-15);
  CHECK((param::closest_point_on_triangle({2, -1, 0}, a, b, c) - b).norm() < 1e-15);
  CHECK((param::closest_point_on_triangle({0.5, -1, 0}, a, b, c) - Eigen::Vector3d(0.5, 0, 0)).norm() < 1e-15);
  CHECK((param::closest_point_on_triangle({1, 1, 0}, a, b, c) - Eigen::Vector3d(0.5, 0.5, 0)).norm() < 1e-15);
}

TEST_CASE("bucketed distance equals brute force") {
  const auto mesh = test::cube_sphere(5);
  const param::SurfaceDistance distance(mesh);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int s = 0; s < 200; ++s) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    double brute = 1e300;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const Eigen::Vector3d q = param::closest_point_on_triangle(
          p, mesh.positions.row(mesh.triangles(f, 0)).transpose(), mesh.positions.row(mesh.triangles(f, 1)).transpose(),
          mesh.positions.row(mesh.triangles(f, 2)).transpose());
      brute = std::min(brute, (q - p).norm());
    }
    CHECK(distance.distance(p) == doctest::Approx(brute).epsilon(1e-12));
  }
}

TEST_CASE("bounded distance queries agree with the exact distance") {
  const auto mesh = test::cube_sphere(6);
  const param::SurfaceDistance distance(mesh);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int s = 0; s < 300; ++s) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const double exact = distance.distance(p);
    CAPTURE(p.transpose());
    for (const double factor : {0.0, 0.5, 0.999, 1.0, 1.001, 2.0}) {
      const double limit = factor * exact;
      // Below the limit the search is exact; at or above it, the limit itself comes back.
      CHECK(distance.distance_below(p, limit) == std::min(limit, exact));
      if (factor != 1.0) CHECK(distance.within(p, limit) == (exact <= limit));  // 1.0: a rounding tie
    }
    CHECK(distance.distance_below(p, std::numeric_limits<double>::infinity()) == exact);
  }
  // A point on the mesh is within 0 of it.
  CHECK(distance.within(mesh.positions.row(3).transpose(), 0.0));
}

TEST_CASE("closest point from a triangle hint: the point, normal and triangle of the plain search") {
  // Points on the mesh's vertices and edges tie between triangles: the hint must not win them.
  const auto mesh = test::cube_sphere(4);
  const param::SurfaceDistance distance(mesh);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::uniform_int_distribution<int> any_face(0, mesh.num_faces() - 1);
  for (int s = 0; s < 300; ++s) {
    Eigen::Vector3d p(u(rng), u(rng), u(rng));
    if (s % 3 == 0) p = mesh.positions.row(mesh.triangles(any_face(rng), 0)).transpose();
    if (s % 3 == 1)
      p = 0.5 * (mesh.positions.row(mesh.triangles(s % mesh.num_faces(), 0)) +
                 mesh.positions.row(mesh.triangles(s % mesh.num_faces(), 1))).transpose();
    Eigen::Vector3d normal, hinted_normal;
    int face = -1;
    const Eigen::Vector3d q = distance.closest_point(p, &normal, &face);
    int hint = any_face(rng);
    const Eigen::Vector3d hinted = distance.closest_point(p, &hinted_normal, &hint);
    CHECK(hinted == q);
    CHECK(hinted_normal == normal);
    CHECK(hint == face);
    // The nearest triangle as hint finds itself.
    int same = face;
    CHECK(distance.closest_point(p, nullptr, &same) == q);
    CHECK(same == face);
  }
}

TEST_CASE("closest point from a kept neighbourhood: the point, normal and triangle of the plain search") {
  // A point walking over and near the surface, through vertices and edges (ties), and jumping.
  const auto mesh = test::cube_sphere(4);
  const param::SurfaceDistance distance(mesh);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> step(0.0, 0.02);
  std::uniform_int_distribution<int> any_face(0, mesh.num_faces() - 1);
  param::SurfaceDistance::Nearby nearby;
  int face = -1, listed_face = -1;
  Eigen::Vector3d p(0.3, 0.2, 1.1);
  for (int s = 0; s < 600; ++s) {
    if (s % 50 == 0) p = 1.3 * mesh.positions.row(mesh.triangles(any_face(rng), 0)).transpose();
    if (s % 7 == 0) p = mesh.positions.row(mesh.triangles(any_face(rng), s % 3)).transpose();
    p += Eigen::Vector3d(step(rng), step(rng), step(rng));
    Eigen::Vector3d normal, listed_normal;
    const Eigen::Vector3d q = distance.closest_point(p, &normal, &face);
    const Eigen::Vector3d listed = distance.closest_point(p, &listed_normal, &listed_face, &nearby);
    CHECK(listed == q);
    CHECK(listed_normal == normal);
    CHECK(listed_face == face);
    p = 0.5 * (p + q);
  }
  CHECK(nearby.radius > 0.0);
}
