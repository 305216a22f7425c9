// SPDX-License-Identifier: MIT
#include "core/mesh/surface_creases.h"

#include <cmath>

#include <doctest/doctest.h>

using namespace volspline;

namespace {

// Two triangles on the edge (0, 1) along x, the second folded up by angle_rad about it.
mesh::TriangleMesh crease_hinge(double angle_rad) {
  mesh::TriangleMesh m;
  m.positions.resize(4, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 0.5, -1, 0, 0.5, std::cos(angle_rad), std::sin(angle_rad);
  m.triangles.resize(2, 3);
  m.triangles << 0, 2, 1, 0, 1, 3;
  return m;
}

// A square sheet of n × n unit squares (two triangles each) in the plane z = 0, vertex (i, j) at
// id j·(n + 1) + i, then moved by `place`.
template <typename Place>
mesh::TriangleMesh sheet(int n, Place place) {
  mesh::TriangleMesh m;
  m.positions.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.positions.row(j * (n + 1) + i) = place(i, j).transpose();
  m.triangles.resize(2 * n * n, 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = j * (n + 1) + i;
      m.triangles.row(2 * (j * n + i)) << v, v + 1, v + n + 2;
      m.triangles.row(2 * (j * n + i) + 1) << v, v + n + 2, v + n + 1;
    }
  return m;
}

}  // namespace

TEST_CASE("crease_triangles: a crease_hinge is a crease when its normals turn by more than the angle") {
  // Normals turn by the crease_hinge angle: 80° is a crease at 75°, 70° is not.
  CHECK(mesh::crease_triangles(crease_hinge(80.0 * M_PI / 180.0), 75.0 * M_PI / 180.0) == std::vector<char>{1, 1});
  CHECK(mesh::crease_triangles(crease_hinge(70.0 * M_PI / 180.0), 75.0 * M_PI / 180.0) == std::vector<char>{0, 0});
}

TEST_CASE("crease_triangles: every triangle of a cube touches a crease, a fine cylinder's none") {
  mesh::TriangleMesh cube;
  cube.positions.resize(8, 3);
  for (int c = 0; c < 8; ++c) cube.positions.row(c) << (c & 1), (c >> 1 & 1), (c >> 2 & 1);
  cube.triangles.resize(12, 3);
  cube.triangles << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5,
      3, 7, 5;
  CHECK(mesh::crease_triangles(cube, 1.3) == std::vector<char>(12, 1));
  // An open cylinder of 64 sides: neighbouring normals 5.6° apart; its rim edges have one triangle.
  const int sides = 64;
  mesh::TriangleMesh cylinder;
  cylinder.positions.resize(2 * sides, 3);
  cylinder.triangles.resize(2 * sides, 3);
  for (int s = 0; s < sides; ++s) {
    const double a = 2.0 * M_PI * s / sides;
    cylinder.positions.row(s) << std::cos(a), std::sin(a), 0;
    cylinder.positions.row(sides + s) << std::cos(a), std::sin(a), 1;
    const int t = (s + 1) % sides;
    cylinder.triangles.row(2 * s) << s, t, sides + s;
    cylinder.triangles.row(2 * s + 1) << t, sides + t, sides + s;
  }
  CHECK(mesh::crease_triangles(cylinder, 1.3) == std::vector<char>(2 * sides, 0));
}

TEST_CASE("SurfaceCreases with a scale: a sliver's stray normal is no crease, a fold of the sheet is") {
  const int n = 16, middle = (n / 2) * (n + 1) + n / 2;
  // The middle vertex moved almost onto its neighbour (i + 1) and lifted a fifth of a square, as
  // marching cubes leaves it: two slivers whose normals turn by more than 75° against their
  // neighbours', in a sheet that is flat at the scale of three edges.
  const mesh::TriangleMesh rippled = sheet(n, [&](int i, int j) {
    return i == n / 2 && j == n / 2 ? Eigen::Vector3d(i + 0.95, j, 0.2) : Eigen::Vector3d(i, j, 0.0);
  });
  CHECK(mesh::SurfaceCreases(rippled, 1.3).vertex_on_crease(middle));
  CHECK(!mesh::SurfaceCreases(rippled, 1.3, 3.0).vertex_on_crease(middle));
  // The sheet folded by 90° along the line i = n/2: a crease at every scale.
  const mesh::TriangleMesh folded = sheet(n, [&](int i, int j) {
    return i <= n / 2 ? Eigen::Vector3d(i, j, 0.0) : Eigen::Vector3d(n / 2, j, i - n / 2);
  });
  const mesh::SurfaceCreases fold(folded, 1.3, 3.0);
  CHECK(fold.vertex_on_crease(middle));
  CHECK(!fold.vertex_on_crease(middle - 2));
  CHECK(mesh::crease_triangles(folded, 1.3, 3.0) == mesh::crease_triangles(folded, 1.3));
}
