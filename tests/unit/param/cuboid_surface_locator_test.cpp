// SPDX-License-Identifier: MIT
#include "core/param/cuboid_surface_locator.h"

#include <doctest/doctest.h>

#include <Eigen/Geometry>

#include "core/param/cuboid_surface_map.h"
#include "core/polycube/cuboid_layout.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

struct Mapped {
  mesh::HalfedgeMesh mesh;
  polycube::CuboidLayout layout;
  param::CuboidSurfaceMap map;
};

Mapped map_of(const mesh::TriangleMesh& input) {
  mesh::HalfedgeMesh m = mesh::HalfedgeMesh::build(input, "test");
  polycube::CuboidLayout layout = polycube::compute_cuboid_layout(m);
  param::CuboidSurfaceMap map = param::compute_cuboid_surface_map(m, layout);
  return {std::move(m), std::move(layout), std::move(map)};
}

}  // namespace

TEST_CASE("cuboid surface locator: on a subdivided cube it is the affine map of the corners") {
  // The map of the cube [-1, 1]³ is the identity up to the scale 1/2 and a cube symmetry, so its
  // inverse is xyz = x0 + 2·R·uvw with R read off the corners (tolerance: the CG residual).
  const Mapped c = map_of(test::subdivided_cube(4));
  const param::CuboidSurfaceLocator locator(c.mesh, c.map);
  const Eigen::Vector3d x0 = c.mesh.vertex_position(c.layout.corners[0]);
  Eigen::Matrix3d r;
  for (int a = 0; a < 3; ++a) r.col(a) = (c.mesh.vertex_position(c.layout.corners[1 << a]) - x0) / 2.0;
  CHECK((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() < 1e-12);  // a signed permutation
  for (int f = 0; f < polycube::num_cube_faces; ++f)
    for (double s : {0.0, 0.13, 0.5, 0.77, 1.0})
      for (double t : {0.0, 0.31, 0.9, 1.0}) {
        const Eigen::Vector3d expected = x0 + 2.0 * r * polycube::cube_face_point(f, s, t);
        CHECK((locator.locate(f, s, t) - expected).norm() < 1e-7);
        CHECK((locator.locate_uvw(polycube::cube_face_point(f, s, t)) - expected).norm() < 1e-7);
      }
}

TEST_CASE("cuboid surface locator: vertices and triangle centroids come back exactly") {
  // On a curved surface the inverse is piecewise linear: a vertex's parameter gives the vertex,
  // the parameter centroid of a triangle gives its centroid (barycentric interpolation).
  const Mapped c = map_of(test::cube_sphere(6));
  REQUIRE(c.map.num_flipped == 0);
  const param::CuboidSurfaceLocator locator(c.mesh, c.map);
  for (int v = 0; v < c.mesh.num_vertices(); ++v)
    CHECK((locator.locate_uvw(c.map.uvw.row(v).transpose()) - c.mesh.vertex_position(v)).norm() < 1e-12);
  for (int f = 0; f < c.mesh.num_faces(); f += 5) {
    const auto corners = c.mesh.face_vertices(f);
    const int face = c.map.face_region[f];
    Eigen::Vector2d st = Eigen::Vector2d::Zero();
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int v : corners) {
      st += polycube::cube_face_coordinates(face, c.map.uvw.row(v).transpose()) / 3.0;
      centroid += c.mesh.vertex_position(v) / 3.0;
    }
    CHECK((locator.locate(face, st.x(), st.y()) - centroid).norm() < 1e-12);
  }
}

TEST_CASE("cuboid surface locator: parameters are clamped, poly-edge points agree between faces") {
  const Mapped c = map_of(test::cube_sphere(5));
  const param::CuboidSurfaceLocator locator(c.mesh, c.map);
  for (int f = 0; f < polycube::num_cube_faces; ++f) {
    CHECK((locator.locate(f, -0.5, 1.5) - locator.locate(f, 0.0, 1.0)).norm() < 1e-15);
    CHECK((locator.locate(f, 2.0, 0.4) - locator.locate(f, 1.0, 0.4)).norm() < 1e-15);
  }
  // Midpoints of the 12 cube edges, each reached from its two faces.
  for (int e = 0; e < polycube::num_cube_edges; ++e) {
    const auto ends = polycube::cube_edge_corners(e);
    Eigen::Vector3d mid = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3; ++a) mid(a) = 0.5 * (((ends[0] >> a) & 1) + ((ends[1] >> a) & 1));
    std::vector<Eigen::Vector3d> from_faces;
    for (int f = 0; f < polycube::num_cube_faces; ++f)
      if (mid(f / 2) == f % 2) {
        const Eigen::Vector2d st = polycube::cube_face_coordinates(f, mid);
        from_faces.push_back(locator.locate(f, st.x(), st.y()));
      }
    REQUIRE(from_faces.size() == 2);
    CHECK((from_faces[0] - from_faces[1]).norm() < 1e-12);
    CHECK(from_faces[0].norm() == doctest::Approx(1.0).epsilon(0.05));  // on the sphere, up to chords
  }
}
