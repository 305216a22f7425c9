// SPDX-License-Identifier: MIT
#include "core/io/obj_format.h"

#include <doctest/doctest.h>

#include "tests/unit/common/test_meshes.h"
#include "tests/unit/io/io_test_util.h"

using namespace volspline::io;
using volspline::io::test::error_of;
using volspline::io::test::has;

TEST_CASE("obj: vertices, comments, slash forms, polygons fan-triangulated") {
  const std::string text =
      "# a quad and a triangle\n"
      "mtllib x.mtl\n"
      "v 0 0 0\r\n"
      "v 1 0 0 1.0\n"
      "v 1 1 0 0.5 0.5 0.5\n"
      "v 0 1 0  # trailing comment\n"
      "vt 0 0\nvn 0 0 1\n"
      "g group\ns off\n"
      "f 1/1/1 2/1/1 3//1 4\n"
      "f -4 -2 -1\n";
  const auto m = parse_obj(text, "q.obj");
  CHECK(m.num_vertices() == 4);
  REQUIRE(m.num_faces() == 3);
  CHECK(m.triangles.row(0) == Eigen::RowVector3i(0, 1, 2));
  CHECK(m.triangles.row(1) == Eigen::RowVector3i(0, 2, 3));
  CHECK(m.triangles.row(2) == Eigen::RowVector3i(0, 2, 3));
  CHECK(m.positions(2, 1) == 1.0);
}

TEST_CASE("obj: relative indices resolve against vertices read so far") {
  const auto m = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -4 -1 -3\n", "r.obj");
  REQUIRE(m.num_faces() == 2);
  CHECK(m.triangles.row(1) == Eigen::RowVector3i(0, 3, 1));
}

TEST_CASE("obj: round trip keeps every double bit for bit") {
  for (const auto& mesh : {volspline::test::tetrahedron(), volspline::test::cube()}) {
    const std::string text = serialize_obj(mesh);
    const auto back = parse_obj(text, "rt.obj");
    CHECK(back.positions == mesh.positions);  // exact: shortest round-trip text
    CHECK(back.triangles == mesh.triangles);
    CHECK(serialize_obj(back) == text);
  }
}

TEST_CASE("obj: errors name the file, line and problem") {
  CHECK(has(error_of([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "b.obj"); }),
            "b.obj:4: face index 9 out of range (3 vertices)"));
  CHECK(has(error_of([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "b.obj"); }),
            "b.obj:4: relative face index -4 out of range"));
  CHECK(has(error_of([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "b.obj"); }), "b.obj:4: face index 0"));
  CHECK(has(error_of([] { parse_obj("v 0 nan 0\n", "n.obj"); }), "n.obj:1: NaN y coordinate"));
  CHECK(has(error_of([] { parse_obj("v 0 0 inf\n", "i.obj"); }), "i.obj:1: infinite z coordinate"));
  CHECK(has(error_of([] { parse_obj("v 0 0 1e999\n", "i.obj"); }), "i.obj:1: infinite z coordinate"));
  CHECK(has(error_of([] { parse_obj("v 0 0\n", "t.obj"); }), "t.obj:1: missing z coordinate"));
  CHECK(has(error_of([] { parse_obj("v 0 x 0\n", "t.obj"); }), "t.obj:1: bad y coordinate 'x'"));
  CHECK(has(error_of([] { parse_obj("v 0 0 0\nv 1 0 0\nf 1 2\n", "t.obj"); }), "t.obj:3: face with 2 corners"));
  CHECK(has(error_of([] { parse_obj("v 0 0 0\nf 1 a 1\n", "t.obj"); }), "t.obj:2: bad face corner 'a'"));
  CHECK(has(error_of([] { parse_obj("", "e.obj"); }), "e.obj: empty file"));
  CHECK(has(error_of([] { parse_obj("# nothing\n", "e.obj"); }), "e.obj: no vertices"));
  CHECK(has(error_of([] { parse_obj("v 0 0 0\nv 1 0 0\n", "e.obj"); }), "e.obj: no faces"));
}
