// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "tests/unit/common/test_meshes.h"

using volspline::Error;
using volspline::mesh::HalfedgeMesh;
using volspline::mesh::no_id;
using volspline::mesh::TriangleMesh;
namespace t = volspline::test;

namespace {

/// Every structural invariant of a built half-edge mesh.
void check_invariants(const HalfedgeMesh& m) {
  REQUIRE(m.num_halfedges() == 2 * m.num_edges());
  for (int h = 0; h < m.num_halfedges(); ++h) {
    CHECK(m.halfedge_twin(m.halfedge_twin(h)) == h);
    CHECK(m.halfedge_twin(h) != h);
    CHECK(m.halfedge_next(m.halfedge_prev(h)) == h);
    CHECK(m.halfedge_prev(m.halfedge_next(h)) == h);
    CHECK(m.halfedge_face(m.halfedge_next(h)) == m.halfedge_face(h));
    CHECK(m.halfedge_source(m.halfedge_next(h)) == m.halfedge_vertex(h));
    CHECK(m.halfedge_edge(m.halfedge_twin(h)) == m.halfedge_edge(h));
    CHECK(!(m.halfedge_is_boundary(h) && m.halfedge_is_boundary(m.halfedge_twin(h))));
    if (!m.halfedge_is_boundary(h)) {
      CHECK(m.halfedge_next(m.halfedge_next(m.halfedge_next(h))) == h);
    }
  }
  for (int f = 0; f < m.num_faces(); ++f) {
    const auto c = m.face_vertices(f);
    const auto hs = m.face_halfedges(f);
    for (int k = 0; k < 3; ++k) {
      CHECK(m.halfedge_source(hs[k]) == c[k]);
      CHECK(m.halfedge_vertex(hs[k]) == c[(k + 1) % 3]);
    }
  }
  for (int v = 0; v < m.num_vertices(); ++v) {
    for (int h : m.vertex_outgoing(v)) CHECK(m.halfedge_source(h) == v);
  }
  for (int e = 0; e < m.num_edges(); ++e) {
    CHECK(m.halfedge_edge(m.edge_halfedge(e)) == e);
    CHECK(!m.halfedge_is_boundary(m.edge_halfedge(e)));
  }
}

std::string build_error(const TriangleMesh& mesh, const std::string& name = "x.off") {
  try {
    HalfedgeMesh::build(mesh, name);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("tetrahedron: counts, invariants, closed rings") {
  const HalfedgeMesh m = HalfedgeMesh::build(t::tetrahedron());
  CHECK(m.num_vertices() == 4);
  CHECK(m.num_faces() == 4);
  CHECK(m.num_edges() == 6);
  CHECK(m.num_halfedges() == 12);
  CHECK(m.num_boundary_halfedges() == 0);
  CHECK(m.consistently_oriented());
  check_invariants(m);
  for (int v = 0; v < 4; ++v) {
    CHECK(!m.vertex_is_boundary(v));
    CHECK(m.vertex_valence(v) == 3);
    int faces = 0;
    for (int f : m.vertex_faces(v)) {
      CHECK(f >= 0);
      ++faces;
    }
    CHECK(faces == 3);
  }
  // Edges are numbered in lexicographic order of their sorted endpoints.
  const std::vector<std::array<int, 2>> expected = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (int e = 0; e < 6; ++e) {
    auto ends = m.edge_vertices(e);
    if (ends[0] > ends[1]) std::swap(ends[0], ends[1]);
    CHECK(ends == expected[e]);
    CHECK(!m.edge_is_boundary(e));
  }
}

TEST_CASE("cube and torus satisfy the invariants") {
  check_invariants(HalfedgeMesh::build(t::unit_cube()));
  const HalfedgeMesh torus = HalfedgeMesh::build(t::torus(8, 5));
  check_invariants(torus);
  CHECK(torus.num_edges() == 3 * 8 * 5);
  for (int v = 0; v < torus.num_vertices(); ++v) CHECK(torus.vertex_valence(v) == 6);
}

TEST_CASE("open square: boundary halfedges form one loop") {
  const HalfedgeMesh m = HalfedgeMesh::build(t::flat_grid(3, 2));
  check_invariants(m);
  CHECK(m.num_boundary_halfedges() == 10);
  const int first = 3 * m.num_faces();
  CHECK(m.halfedge_face(first) == no_id);
  int length = 0;
  int h = first;
  do {
    CHECK(m.halfedge_is_boundary(h));
    CHECK(m.vertex_is_boundary(m.halfedge_vertex(h)));
    h = m.halfedge_next(h);
    ++length;
  } while (h != first && length < 100);
  CHECK(length == 10);
  // Interior vertices (1,1), (2,1) are not on the boundary.
  CHECK(!m.vertex_is_boundary(5));
  CHECK(!m.vertex_is_boundary(6));
  CHECK(m.vertex_is_boundary(0));
}

TEST_CASE("one-ring order is counter-clockwise at interior and boundary vertices") {
  const TriangleMesh grid = t::flat_grid(2, 2);
  const HalfedgeMesh m = HalfedgeMesh::build(grid);
  const double pi = 3.14159265358979323846;
  auto angle = [&](int centre, int v) {
    const Eigen::Vector3d d = m.vertex_position(v) - m.vertex_position(centre);
    return std::atan2(d.y(), d.x());
  };

  SUBCASE("interior vertex: a full turn of 2π in 6 positive steps") {
    const int centre = 4;
    std::vector<int> ring(m.vertex_neighbors(centre).begin(), m.vertex_neighbors(centre).end());
    REQUIRE(ring.size() == 6);
    double turn = 0.0;
    for (size_t i = 0; i < ring.size(); ++i) {
      double step = angle(centre, ring[(i + 1) % ring.size()]) - angle(centre, ring[i]);
      if (step < 0) step += 2 * pi;
      CHECK(step > 0.0);
      CHECK(step < pi);
      turn += step;
    }
    CHECK(turn == doctest::Approx(2 * pi).epsilon(1e-12));
    // Face i lies between neighbours i and i+1.
    std::vector<int> faces(m.vertex_faces(centre).begin(), m.vertex_faces(centre).end());
    REQUIRE(faces.size() == 6);
    for (size_t i = 0; i < faces.size(); ++i) {
      const auto c = m.face_vertices(faces[i]);
      const int a = ring[i], b = ring[(i + 1) % ring.size()];
      CHECK((c[0] == a || c[1] == a || c[2] == a));
      CHECK((c[0] == b || c[1] == b || c[2] == b));
    }
  }

  SUBCASE("boundary vertex: from the right boundary neighbour to the left one") {
    const int centre = 1;  // (1, 0), bottom edge
    std::vector<int> ring(m.vertex_neighbors(centre).begin(), m.vertex_neighbors(centre).end());
    REQUIRE(ring.size() == 4);
    CHECK(ring.front() == 2);
    CHECK(ring.back() == 0);
    for (size_t i = 0; i + 1 < ring.size(); ++i) {
      CHECK(angle(centre, ring[i]) < angle(centre, ring[i + 1]));
    }
    std::vector<int> faces(m.vertex_faces(centre).begin(), m.vertex_faces(centre).end());
    CHECK(faces.size() == 3);
    std::vector<int> out(m.vertex_outgoing(centre).begin(), m.vertex_outgoing(centre).end());
    CHECK(!m.halfedge_is_boundary(out.front()));
    CHECK(m.halfedge_is_boundary(m.halfedge_twin(out.front())));
    CHECK(m.halfedge_is_boundary(out.back()));
  }

  SUBCASE("corner vertex with a single face") {
    const int centre = 2;  // (2, 0): only face (1, 2, 5)... one face touches it
    std::vector<int> ring(m.vertex_neighbors(centre).begin(), m.vertex_neighbors(centre).end());
    CHECK(ring == std::vector<int>{5, 1});
    CHECK(m.vertex_valence(centre) == 2);
  }
}

TEST_CASE("unreferenced vertices are kept and counted") {
  TriangleMesh mesh = t::tetrahedron();
  mesh.positions.conservativeResize(6, 3);
  mesh.positions.row(4) << 9, 9, 9;
  mesh.positions.row(5) << 8, 8, 8;
  const HalfedgeMesh m = HalfedgeMesh::build(mesh);
  CHECK(m.num_vertices() == 6);
  CHECK(m.num_unreferenced_vertices() == 2);
  CHECK(m.vertex_halfedge(4) == no_id);
  CHECK(!m.vertex_is_boundary(4));
  CHECK(m.vertex_valence(5) == 0);
  CHECK(m.vertex_neighbors(5).begin() == m.vertex_neighbors(5).end());
  check_invariants(m);
}

TEST_CASE("flipped faces of an orientable mesh are reoriented and reported") {
  TriangleMesh mesh = t::tetrahedron();
  std::swap(mesh.triangles(3, 1), mesh.triangles(3, 2));
  SUBCASE("one face flipped: the majority seeded at face 0 wins") {
    const HalfedgeMesh m = HalfedgeMesh::build(mesh);
    CHECK(!m.consistently_oriented());
    CHECK(m.num_flipped_faces() == 1);
    CHECK(m.face_is_flipped(3));
    CHECK(!m.face_is_flipped(0));
    CHECK(m.triangles().row(3) == t::tetrahedron().triangles.row(3));
    check_invariants(m);
  }
  SUBCASE("face 0 is the seed even when it is in the minority") {
    std::swap(mesh.triangles(0, 1), mesh.triangles(0, 2));
    const HalfedgeMesh m = HalfedgeMesh::build(mesh);
    CHECK(m.num_flipped_faces() == 2);
    CHECK(!m.face_is_flipped(0));
    CHECK(m.face_is_flipped(1));
    CHECK(m.face_is_flipped(2));
    CHECK(!m.face_is_flipped(3));
    check_invariants(m);
  }
  SUBCASE("the same triangle twice becomes a closed two-face pillow") {
    const HalfedgeMesh m = HalfedgeMesh::build(t::make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0},
                                                            {0, 1, 2, 0, 1, 2}));
    CHECK(m.num_flipped_faces() == 1);
    CHECK(m.num_boundary_halfedges() == 0);
    check_invariants(m);
  }
}

TEST_CASE("build is deterministic") {
  const TriangleMesh mesh = t::torus(7, 4);
  const HalfedgeMesh a = HalfedgeMesh::build(mesh);
  const HalfedgeMesh b = HalfedgeMesh::build(mesh);
  for (int h = 0; h < a.num_halfedges(); ++h) {
    CHECK(a.halfedge_twin(h) == b.halfedge_twin(h));
    CHECK(a.halfedge_next(h) == b.halfedge_next(h));
    CHECK(a.halfedge_edge(h) == b.halfedge_edge(h));
  }
  for (int v = 0; v < a.num_vertices(); ++v) CHECK(a.vertex_halfedge(v) == b.vertex_halfedge(v));
}

TEST_CASE("to_triangle_mesh round-trips a consistently oriented mesh") {
  const TriangleMesh mesh = t::unit_cube();
  const TriangleMesh back = HalfedgeMesh::build(mesh).to_triangle_mesh();
  CHECK(back.positions == mesh.positions);
  CHECK(back.triangles == mesh.triangles);
}

TEST_CASE("rejections name the first offending element") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();

  SUBCASE("no faces") {
    TriangleMesh mesh = t::tetrahedron();
    mesh.triangles.resize(0, 3);
    CHECK(build_error(mesh) == "mesh 'x.off': has no faces");
  }
  SUBCASE("vertex id out of range") {
    TriangleMesh mesh = t::tetrahedron();
    mesh.triangles(2, 1) = 4;
    mesh.triangles(3, 0) = 7;
    CHECK(build_error(mesh) == "mesh 'x.off': face 2 has vertex id 4 out of range [0, 4)");
    mesh.triangles(1, 2) = -1;
    CHECK(build_error(mesh) == "mesh 'x.off': face 1 has vertex id -1 out of range [0, 4)");
  }
  SUBCASE("face repeating a vertex") {
    TriangleMesh mesh = t::tetrahedron();
    mesh.triangles.row(1) << 3, 1, 3;
    CHECK(build_error(mesh) == "mesh 'x.off': face 1 repeats vertex 3 (3, 1, 3)");
  }
  SUBCASE("non-finite coordinates") {
    TriangleMesh mesh = t::tetrahedron();
    mesh.positions(3, 1) = inf;
    mesh.positions(2, 0) = nan;
    CHECK(build_error(mesh) == "mesh 'x.off': vertex 2 has a non-finite coordinate (nan, 1, 0)");
    mesh.positions(2, 0) = 0.0;
    CHECK(build_error(mesh) == "mesh 'x.off': vertex 3 has a non-finite coordinate (0, inf, 1)");
  }
  SUBCASE("edge with three faces") {
    const TriangleMesh mesh = t::make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1},
                                           {0, 1, 2, 1, 0, 3, 4, 1, 0});
    CHECK(build_error(mesh) == "mesh 'x.off': edge (0, 1) is shared by 3 faces (first: 0, 1, 2)");
  }
  SUBCASE("the edge with more than two faces whose first face is lowest is named") {
    // Edge (2, 3) has faces 0, 3, 4; edge (0, 1) has faces 1, 2, 5, 6.
    const TriangleMesh mesh = t::make_mesh(
        {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1, 2, 2, 2},
        {2, 3, 4, 0, 1, 4, 1, 0, 5, 3, 2, 6, 3, 2, 7, 0, 1, 6, 1, 0, 7});
    CHECK(build_error(mesh) == "mesh 'x.off': edge (2, 3) is shared by 3 faces (first: 0, 3, 4)");
  }
  SUBCASE("non-manifold vertex: two triangles touching at a vertex") {
    const TriangleMesh mesh =
        t::make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0}, {0, 1, 2, 0, 3, 4});
    CHECK(build_error(mesh) == "mesh 'x.off': vertex 0 is non-manifold: its faces form 2 separate fans");
  }
  SUBCASE("non-manifold vertex: two closed tetrahedra sharing a vertex") {
    TriangleMesh mesh = t::two_tetrahedra();
    for (int f = 4; f < 8; ++f) {
      for (int k = 0; k < 3; ++k) {
        if (mesh.triangles(f, k) == 7) mesh.triangles(f, k) = 2;
      }
    }
    CHECK(build_error(mesh) == "mesh 'x.off': vertex 2 is non-manifold: its faces form 2 separate fans");
  }
  SUBCASE("non-orientable surface") {
    // Orientation spreads from face 0 both ways round the strip and clashes opposite to it.
    CHECK(build_error(t::mobius_strip(6), "strip.obj") ==
          "mesh 'strip.obj': the surface is not orientable: faces 5 and 6 at edge (3, 9) "
          "cannot be oriented consistently with their neighbours");
  }
  SUBCASE("default source name") {
    TriangleMesh mesh = t::tetrahedron();
    mesh.triangles.resize(0, 3);
    try {
      HalfedgeMesh::build(mesh);
      FAIL("expected an error");
    } catch (const Error& e) {
      CHECK(std::string(e.what()) == "mesh 'mesh': has no faces");
    }
  }
}
