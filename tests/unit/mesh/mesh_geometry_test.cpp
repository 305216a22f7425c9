// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <numeric>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_geometry.h"
#include "tests/unit/common/test_meshes.h"

using volspline::mesh::HalfedgeMesh;
using volspline::mesh::Positions;
using volspline::mesh::TriangleMesh;
namespace mesh = volspline::mesh;
namespace t = volspline::test;

TEST_CASE("unit cube: face areas sum to 6, normals are outward axes") {
  const HalfedgeMesh cube = HalfedgeMesh::build(t::unit_cube());
  const std::vector<double> areas = mesh::face_areas(cube);
  REQUIRE(areas.size() == 12);
  for (double a : areas) CHECK(a == 0.5);  // exact: half a unit square
  CHECK(std::accumulate(areas.begin(), areas.end(), 0.0) == 6.0);

  const Positions normals = mesh::face_normals(cube);
  for (int f = 0; f < 12; ++f) {
    const Eigen::Vector3d n = normals.row(f).transpose();
    CHECK(n.norm() == doctest::Approx(1.0).epsilon(1e-15));
    CHECK(n.cwiseAbs().maxCoeff() == 1.0);  // axis-aligned
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int v : cube.face_vertices(f)) centroid += cube.vertex_position(v) / 3.0;
    CHECK(n.dot(centroid - Eigen::Vector3d(0.5, 0.5, 0.5)) > 0.0);
  }
}

TEST_CASE("vertex normals follow the analytic normal of a torus") {
  const double pi = 3.14159265358979323846;
  const int nu = 40, nv = 24;
  const HalfedgeMesh torus = HalfedgeMesh::build(t::torus(nu, nv, 1.0, 0.3));
  const Positions normals = mesh::vertex_normals(torus);
  double worst = 1.0;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
      const Eigen::Vector3d exact(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
      const Eigen::Vector3d n = normals.row(i * nv + j).transpose();
      CHECK(n.norm() == doctest::Approx(1.0).epsilon(1e-14));
      worst = std::min(worst, n.dot(exact));
    }
  }
  // The split direction of the quads tilts the discrete normal by O(h); 0.99 is about 8°.
  CHECK(worst > 0.99);
}

TEST_CASE("degenerate faces and unreferenced vertices get zero normals") {
  TriangleMesh squashed = t::tetrahedron();
  squashed.positions.row(3) << 0.5, 0.0, 0.0;
  squashed.positions.conservativeResize(5, 3);
  squashed.positions.row(4) << 7, 7, 7;
  const HalfedgeMesh m = HalfedgeMesh::build(squashed);
  CHECK(mesh::face_normals(m).row(1).norm() == 0.0);
  CHECK(mesh::face_areas(m)[1] == 0.0);
  CHECK(mesh::vertex_normals(m).row(4).norm() == 0.0);
}

TEST_CASE("edge lengths of the unit cube") {
  const HalfedgeMesh cube = HalfedgeMesh::build(t::unit_cube());
  const std::vector<double> lengths = mesh::edge_lengths(cube);
  REQUIRE(lengths.size() == 18);
  int unit = 0, diagonal = 0;
  for (double l : lengths) {
    if (l == 1.0) ++unit;
    if (l == std::sqrt(2.0)) ++diagonal;
  }
  CHECK(unit == 12);
  CHECK(diagonal == 6);
}
