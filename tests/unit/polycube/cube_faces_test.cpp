// SPDX-License-Identifier: MIT
#include "core/polycube/cube_faces.h"

#include <doctest/doctest.h>

#include <algorithm>

#include <Eigen/Geometry>

#include "core/polycube/cuboid_layout.h"

using namespace volspline;

TEST_CASE("cube face coordinates: the in-plane axes of each face, and their inverse") {
  // Face f lies on (axis f/2) = f % 2; s, t are the axes (f/2 + 1) % 3 and (f/2 + 2) % 3.
  const Eigen::Vector3d p(0.1, 0.2, 0.3);
  CHECK(polycube::cube_face_coordinates(0, p) == Eigen::Vector2d(0.2, 0.3));  // u = 0: (v, w)
  CHECK(polycube::cube_face_coordinates(3, p) == Eigen::Vector2d(0.3, 0.1));  // v = 1: (w, u)
  CHECK(polycube::cube_face_coordinates(4, p) == Eigen::Vector2d(0.1, 0.2));  // w = 0: (u, v)
  CHECK(polycube::cube_face_point(0, 0.2, 0.3) == Eigen::Vector3d(0.0, 0.2, 0.3));
  CHECK(polycube::cube_face_point(3, 0.3, 0.1) == Eigen::Vector3d(0.1, 1.0, 0.3));
  CHECK(polycube::cube_face_point(5, 0.25, 0.75) == Eigen::Vector3d(0.25, 0.75, 1.0));
  for (int f = 0; f < polycube::num_cube_faces; ++f)
    for (double s : {0.0, 0.3, 1.0})
      for (double t : {0.0, 0.6, 1.0}) {
        const Eigen::Vector3d q = polycube::cube_face_point(f, s, t);
        CHECK(q(f / 2) == f % 2);
        CHECK(polycube::cube_face_coordinates(f, q) == Eigen::Vector2d(s, t));
      }
}

TEST_CASE("cube face coordinates: triangles seen from outside turn counter-clockwise on the high faces") {
  // The (s, t) axes of face f and its outward normal: ŝ × t̂ = +e_a, so (s, t) is a right-handed
  // frame seen from outside on the high face (normal +e_a) and a mirrored one on the low face.
  for (int f = 0; f < polycube::num_cube_faces; ++f) {
    const Eigen::Vector3d o = polycube::cube_face_point(f, 0, 0);
    const Eigen::Vector3d s = polycube::cube_face_point(f, 1, 0) - o, t = polycube::cube_face_point(f, 0, 1) - o;
    Eigen::Vector3d outward = Eigen::Vector3d::Zero();
    outward(f / 2) = f % 2 == 1 ? 1.0 : -1.0;
    CHECK(s.cross(t).dot(outward) == (f % 2 == 1 ? 1.0 : -1.0));
  }
}

TEST_CASE("cube face corners lie on their face, in cyclic order") {
  for (int f = 0; f < polycube::num_cube_faces; ++f) {
    const auto corners = polycube::cube_face_corners(f);
    for (int k = 0; k < 4; ++k) {
      // Neighbours in the cycle differ in one bit (share a cube edge of the face).
      const int a = corners[k], b = corners[(k + 1) % 4];
      const int diff = a ^ b;
      CHECK((diff != 0 && (diff & (diff - 1)) == 0));
      const int e = polycube::cube_edge_between(a, b);
      const auto edges = polycube::cube_face_edges(f);
      CHECK(std::find(edges.begin(), edges.end(), e) != edges.end());
    }
  }
}

TEST_CASE("CubeFaceSet: empty, all, with, without") {
  constexpr polycube::CubeFaceSet none;
  CHECK(none.empty());
  for (int f = 0; f < 6; ++f) CHECK_FALSE(none.contains(f));
  const polycube::CubeFaceSet all = polycube::CubeFaceSet::all();
  for (int f = 0; f < 6; ++f) CHECK(all.contains(f));
  const polycube::CubeFaceSet two = none.with(1).with(4);
  CHECK(two.contains(1));
  CHECK(two.contains(4));
  CHECK_FALSE(two.contains(0));
  CHECK(two.without(1).without(4) == none);
  CHECK(all.without(3) != all);
  CHECK(all.without(3).with(3) == all);
  CHECK(all.with(2) == all);
  CHECK(none.without(5) == none);
}
