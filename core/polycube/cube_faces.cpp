// SPDX-License-Identifier: MIT
#include "core/polycube/cube_faces.h"

namespace volspline::polycube {

Eigen::Vector2d cube_face_coordinates(int face, const Eigen::Vector3d& uvw) {
  const int a = face / 2;
  return Eigen::Vector2d(uvw((a + 1) % 3), uvw((a + 2) % 3));
}

Eigen::Vector3d cube_face_point(int face, double s, double t) {
  const int a = face / 2;
  Eigen::Vector3d uvw;
  uvw(a) = face % 2;
  uvw((a + 1) % 3) = s;
  uvw((a + 2) % 3) = t;
  return uvw;
}

}  // namespace volspline::polycube
