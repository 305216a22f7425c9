// SPDX-License-Identifier: MIT
#include "core/io/off_format.h"

#include <doctest/doctest.h>

#include "tests/unit/common/test_meshes.h"
#include "tests/unit/io/io_test_util.h"

using namespace volspline::io;
using volspline::io::test::error_of;
using volspline::io::test::has;

TEST_CASE("off: comments, colour columns ignored, polygons fan-triangulated") {
  const std::string text =
      "# comment before header\nCOFF\n# counts next\n5 2 0\n"
      "0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n1 1 0 1 1 1 1\n0 1 0 0 0 0 0\n\n0.5 0.5 1 # apex\n"
      "4 0 1 2 3 0.1 0.2 0.3\n3 0 1 4\n";
  const auto m = parse_off(text, "c.off");
  CHECK(m.num_vertices() == 5);
  REQUIRE(m.num_faces() == 3);
  CHECK(m.triangles.row(1) == Eigen::RowVector3i(0, 2, 3));
  CHECK(m.positions(4, 2) == 1.0);
}

TEST_CASE("off: counts on the header line") {
  const auto m = parse_off("OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "h.off");
  CHECK(m.num_faces() == 1);
}

TEST_CASE("off: round trip keeps every double bit for bit") {
  for (const auto& mesh : {volspline::test::tetrahedron(), volspline::test::cube()}) {
    const std::string text = serialize_off(mesh);
    const auto back = parse_off(text, "rt.off");
    CHECK(back.positions == mesh.positions);
    CHECK(back.triangles == mesh.triangles);
    CHECK(serialize_off(back) == text);
  }
}

TEST_CASE("off: errors name the file and problem") {
  const std::string head = "OFF\n3 1 0\n0 0 0\n1 0 0\n";
  CHECK(has(error_of([&] { parse_off(head, "t.off"); }), "t.off: truncated: file ends at vertex 2 of 3"));
  CHECK(has(error_of([&] { parse_off(head + "0 1 0\n", "t.off"); }), "t.off: truncated: file ends at face 0 of 1"));
  CHECK(has(error_of([&] { parse_off(head + "0 1 0\n3 0 1 3\n", "i.off"); }),
            "i.off:6: face index 3 out of range (3 vertices)"));
  CHECK(has(error_of([&] { parse_off(head + "0 1 0\n3 0 -1 2\n", "i.off"); }), "i.off:6: face index -1 out of range"));
  CHECK(has(error_of([&] { parse_off(head + "0 nan 0\n3 0 1 2\n", "n.off"); }), "n.off:5: NaN y coordinate"));
  CHECK(has(error_of([&] { parse_off(head + "0 -inf 0\n3 0 1 2\n", "n.off"); }), "n.off:5: infinite y coordinate"));
  CHECK(has(error_of([&] { parse_off(head + "0 1 0\n2 0 1\n", "s.off"); }), "s.off:6: face 0 has 2 vertices"));
  CHECK(has(error_of([&] { parse_off(head + "0 1 0\n3 0 1\n", "s.off"); }), "s.off:6: missing face index"));
  CHECK(has(error_of([] { parse_off("OFF\n-3 1 0\n", "c.off"); }), "c.off:2: negative vertex count -3"));
  CHECK(has(error_of([] { parse_off("OFF\n3 -1 0\n", "c.off"); }), "c.off:2: negative face count -1"));
  CHECK(has(error_of([] { parse_off("OFF\n1000000000000 1 0\n0 0 0\n", "h.off"); }),
            "h.off:2: vertex count 1000000000000 too large"));
  CHECK(has(error_of([] { parse_off("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", "f.off"); }), "f.off: no faces"));
  CHECK(has(error_of([] { parse_off("", "e.off"); }), "e.off: empty file"));
  CHECK(has(error_of([] { parse_off("# only a comment\n", "e.off"); }), "e.off: empty file"));
  CHECK(has(error_of([] { parse_off("PLY\n3 1 0\n", "b.off"); }), "b.off:1: not an OFF file"));
  CHECK(has(error_of([] { parse_off("OFF\n", "b.off"); }), "b.off:1: missing vertex/face counts"));
}
