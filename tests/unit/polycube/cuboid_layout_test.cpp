// SPDX-License-Identifier: MIT
#include "core/polycube/cuboid_layout.h"

#include <algorithm>
#include <array>
#include <set>
#include <string>

#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

std::string error_of(const mesh::HalfedgeMesh& m, const std::vector<int>& corners) {
  try {
    polycube::CuboidLayoutOptions options;
    options.corners = corners;
    polycube::compute_cuboid_layout(m, options);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("cube topology helpers are consistent") {
  std::set<std::pair<int, int>> seen;
  for (int e = 0; e < polycube::num_cube_edges; ++e) {
    const auto c = polycube::cube_edge_corners(e);
    CHECK((c[0] ^ c[1]) == (1 << (e / 4)));
    CHECK(polycube::cube_edge_between(c[0], c[1]) == e);
    CHECK(polycube::cube_edge_between(c[1], c[0]) == e);
    seen.insert({c[0], c[1]});
  }
  CHECK(seen.size() == 12);
  for (int f = 0; f < polycube::num_cube_faces; ++f) {
    const auto corners = polycube::cube_face_corners(f);
    for (int c : corners) CHECK(((c >> (f / 2)) & 1) == f % 2);
    const auto edges = polycube::cube_face_edges(f);
    CHECK(std::set<int>(edges.begin(), edges.end()).size() == 4);
  }
}

TEST_CASE("the layout of a subdivided cube finds its 8 corners and 6 faces") {
  const auto m = mesh::HalfedgeMesh::build(test::subdivided_cube(4), "cube");
  const auto layout = polycube::compute_cuboid_layout(m);
  // Every corner is a geometric corner of the cube.
  for (int v : layout.corners) CHECK(m.vertex_position(v).cwiseAbs().minCoeff() == doctest::Approx(1.0));
  CHECK(std::set<int>(layout.corners.begin(), layout.corners.end()).size() == 8);
  // Paths share only their end corners; each cube face gets 2·4² triangles (the straight edges).
  std::vector<int> uses(m.num_vertices(), 0);
  for (const auto& path : layout.poly_edges) {
    REQUIRE(path.size() >= 2);
    for (std::size_t i = 1; i + 1 < path.size(); ++i) ++uses[path[i]];
  }
  for (int c : layout.corners) CHECK(uses[c] == 0);
  CHECK(*std::max_element(uses.begin(), uses.end()) <= 1);
  std::vector<int> count(6, 0);
  for (int r : layout.face_region) ++count[r];
  for (int c : count) CHECK(c == 32);
  CHECK(layout.min_corner_distance_rel == doctest::Approx(2.0 / std::sqrt(12.0)));
}

TEST_CASE("the automatic corners do not depend on the pose of the input") {
  const auto base = test::cube_sphere(6);
  const auto a = polycube::compute_cuboid_layout(mesh::HalfedgeMesh::build(test::subdivided_cube(4)));
  const auto b = polycube::compute_cuboid_layout(
      mesh::HalfedgeMesh::build(test::rotated(test::subdivided_cube(4), 0.7, Eigen::Vector3d(1, 2, 3))));
  CHECK(std::set<int>(a.corners.begin(), a.corners.end()) == std::set<int>(b.corners.begin(), b.corners.end()));
  // A sphere lays out into 6 regions of comparable size (no slivers).
  const auto s = polycube::compute_cuboid_layout(mesh::HalfedgeMesh::build(base));
  std::vector<int> count(6, 0);
  for (int r : s.face_region) ++count[r];
  CHECK(*std::min_element(count.begin(), count.end()) > base.num_faces() / 20);
  CHECK(s.min_corner_distance_rel > 0.2);
}

TEST_CASE("user corners are checked") {
  const auto cube = test::subdivided_cube(2);
  const auto m = mesh::HalfedgeMesh::build(cube, "c.off");
  const auto automatic = polycube::compute_cuboid_layout(m);
  std::vector<int> good(automatic.corners.begin(), automatic.corners.end());
  polycube::CuboidLayoutOptions options;
  options.corners = good;
  CHECK(polycube::compute_cuboid_layout(m, options).corners == automatic.corners);
  CHECK(error_of(m, {1, 2, 3}).find("expected 8 corner vertex ids, got 3") != std::string::npos);
  auto repeated = good;
  repeated[1] = repeated[0];
  CHECK(error_of(m, repeated).find("listed twice") != std::string::npos);
  auto outside = good;
  outside[3] = 999;
  CHECK(error_of(m, outside).find("corner 3 is vertex 999") != std::string::npos);
  auto mirrored = good;
  std::swap(mirrored[0], mirrored[1]);
  std::swap(mirrored[2], mirrored[3]);
  std::swap(mirrored[4], mirrored[5]);
  std::swap(mirrored[6], mirrored[7]);
  CHECK(error_of(m, mirrored).find("mirrored") != std::string::npos);
}

TEST_CASE("on a subdivided cube every poly-edge is a straight cube edge: n + 1 vertices, length 2") {
  const int n = 4;
  const auto m = mesh::HalfedgeMesh::build(test::subdivided_cube(n), "cube");
  const auto layout = polycube::compute_cuboid_layout(m);
  for (int e = 0; e < polycube::num_cube_edges; ++e) {
    const auto& path = layout.poly_edges[e];
    REQUIRE(path.size() == static_cast<std::size_t>(n + 1));
    CHECK(path.front() == layout.corners[polycube::cube_edge_corners(e)[0]]);
    CHECK(path.back() == layout.corners[polycube::cube_edge_corners(e)[1]]);
    double length = 0.0;
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
      length += (m.vertex_position(path[i + 1]) - m.vertex_position(path[i])).norm();
    CHECK(length == doctest::Approx(2.0).epsilon(1e-12));
    // Corners of one cube edge differ in one coordinate of the geometric cube: the edge is straight.
    const Eigen::Vector3d d = m.vertex_position(path.back()) - m.vertex_position(path.front());
    CHECK(d.norm() == doctest::Approx(2.0).epsilon(1e-12));
  }
}

TEST_CASE("complete_cuboid_layout: given corners give the shortest paths, prescribed paths are kept") {
  const auto m = mesh::HalfedgeMesh::build(test::subdivided_cube(4), "cube");
  const polycube::CuboidLayout automatic = polycube::compute_cuboid_layout(m);
  for (int band_axis = 0; band_axis < 3; ++band_axis) {
    polycube::CuboidLayout layout;
    layout.corners = automatic.corners;
    std::array<std::vector<int>, polycube::num_cube_edges> fixed;
    fixed[0] = automatic.poly_edges[0];
    std::string why;
    REQUIRE(polycube::complete_cuboid_layout(m, band_axis, fixed, layout, &why));
    CHECK(why.empty());
    CHECK(layout.poly_edges[0] == automatic.poly_edges[0]);
    std::vector<int> count(6, 0);
    for (int r : layout.face_region) ++count[r];
    for (int c : count) CHECK(c == 32);  // 2·4² triangles per cube face
    for (const auto& path : layout.poly_edges) CHECK(path.size() == 5);
  }
}

TEST_CASE("complete_cuboid_layout: a mirrored corner order is refused (its face maps would all flip)") {
  const auto m = mesh::HalfedgeMesh::build(test::subdivided_cube(4), "cube");
  const polycube::CuboidLayout automatic = polycube::compute_cuboid_layout(m);
  // Corner c takes the vertex of corner c^1: the box mirrored along its first axis. Every region
  // is still one face's disc bounded by that face's 4 poly-edges.
  polycube::CuboidLayout mirrored;
  for (int c = 0; c < polycube::num_cube_corners; ++c) mirrored.corners[c] = automatic.corners[c ^ 1];
  std::string why;
  CHECK_FALSE(polycube::complete_cuboid_layout(m, 2, {}, mirrored, &why));
  CHECK(why.find("mirrored") != std::string::npos);
  polycube::CuboidLayout layout;
  layout.corners = automatic.corners;
  CHECK(polycube::complete_cuboid_layout(m, 2, {}, layout, &why));
}

TEST_CASE("candidate_cuboid_layouts: distinct corner sets, each laid out, the first is compute_cuboid_layout's") {
  const auto m = mesh::HalfedgeMesh::build(test::cube_sphere(6), "sphere");
  const auto first = polycube::compute_cuboid_layout(m);
  const auto layouts = polycube::candidate_cuboid_layouts(m, 6);
  REQUIRE(!layouts.empty());
  CHECK(layouts.size() <= 6);
  CHECK(layouts.front().corners == first.corners);
  CHECK(layouts.front().poly_edges == first.poly_edges);
  for (std::size_t k = 0; k < layouts.size(); ++k) {
    CHECK(std::set<int>(layouts[k].corners.begin(), layouts[k].corners.end()).size() == 8);
    for (std::size_t j = 0; j < k; ++j) CHECK(layouts[j].corners != layouts[k].corners);
    std::vector<int> count(6, 0);
    for (int r : layouts[k].face_region) ++count[r];
    CHECK(*std::min_element(count.begin(), count.end()) > 0);
  }
  CHECK(polycube::candidate_cuboid_layouts(m, 1).size() == 1);
}
