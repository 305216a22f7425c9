// SPDX-License-Identifier: MIT
#include "core/io/stl_format.h"

#include <cstdint>
#include <cstring>
#include <limits>

#include <doctest/doctest.h>

#include "tests/unit/common/test_meshes.h"
#include "tests/unit/io/io_test_util.h"

using namespace volspline::io;
using volspline::io::test::error_of;
using volspline::io::test::has;

namespace {

// Binary STL of the mesh's triangles (unindexed, as STL stores them).
std::string binary_stl(const volspline::mesh::TriangleMesh& mesh, std::uint32_t claimed) {
  std::string out(80, ' ');
  out.replace(0, 5, "solid");  // binary files that start with "solid" must still be binary
  out.append(reinterpret_cast<const char*>(&claimed), 4);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const float normal[3] = {0, 0, 0};
    out.append(reinterpret_cast<const char*>(normal), 12);
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) {
        const float value = static_cast<float>(mesh.positions(mesh.triangles(f, k), c));
        out.append(reinterpret_cast<const char*>(&value), 4);
      }
    }
    out.append(2, '\0');
  }
  return out;
}

const char* kAsciiTriangle =
    "solid t\n"
    "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n      vertex 0 1 0\n"
    "    endloop\n  endfacet\n"
    "  facet normal 0 0 1\n    outer loop\n      vertex 1 0 0\n      vertex 1 1 0\n      vertex 0 1 0\n"
    "    endloop\n  endfacet\n"
    "endsolid t\n";

}  // namespace

TEST_CASE("stl: binary corners are merged exactly, numbered by first appearance") {
  const auto tet = volspline::test::tetrahedron();
  const auto m = parse_stl(binary_stl(tet, 4), "t.stl");
  CHECK(m.num_vertices() == 4);
  REQUIRE(m.num_faces() == 4);
  // First triangle (0,2,1) gives ids 0,1,2 in appearance order; vertex 3 appears last.
  CHECK(m.triangles.row(0) == Eigen::RowVector3i(0, 1, 2));
  CHECK(m.positions.row(1) == tet.positions.row(2));
  CHECK(m.triangles.row(1) == Eigen::RowVector3i(0, 2, 3));
  CHECK(parse_stl(binary_stl(tet, 4), "t.stl").positions == m.positions);  // deterministic
}

TEST_CASE("stl: ascii with shared corners") {
  const auto m = parse_stl(kAsciiTriangle, "a.stl");
  CHECK(m.num_vertices() == 4);
  REQUIRE(m.num_faces() == 2);
  CHECK(m.triangles.row(1) == Eigen::RowVector3i(1, 3, 2));
}

TEST_CASE("stl: errors name the file and problem") {
  const auto tet = volspline::test::tetrahedron();
  const std::string good = binary_stl(tet, 4);
  CHECK(has(error_of([&] { parse_stl(good.substr(0, good.size() - 10), "b.stl"); }),
            "b.stl: binary STL size mismatch: header says 4 triangles (284 bytes) but the file has 274 bytes"));
  CHECK(has(error_of([&] { parse_stl(binary_stl(tet, 0).substr(0, 84), "z.stl"); }), "z.stl: no faces"));
  std::string nan = good;
  const float bad = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&nan[84 + 50 + 12 + 4], &bad, 4);
  CHECK(has(error_of([&] { parse_stl(nan, "n.stl"); }), "n.stl: triangle 1: NaN coordinate"));
  std::string inf = good;
  const float big = std::numeric_limits<float>::infinity();
  std::memcpy(&inf[84 + 12], &big, 4);
  CHECK(has(error_of([&] { parse_stl(inf, "i.stl"); }), "i.stl: triangle 0: infinite coordinate"));
  CHECK(has(error_of([] { parse_stl("abc", "s.stl"); }), "s.stl: truncated binary STL (3 bytes"));
  CHECK(has(error_of([] { parse_stl("", "e.stl"); }), "e.stl: empty file"));

  const std::string text = kAsciiTriangle;
  CHECK(has(error_of([&] { parse_stl(text.substr(0, text.find("endloop")), "t.stl"); }),
            "t.stl: truncated: file ends inside facet 0"));
  CHECK(has(error_of([&] { parse_stl(text.substr(0, text.find("endsolid")), "t.stl"); }),
            "t.stl: truncated: no 'endsolid'"));
  std::string nan_text = text;
  nan_text.replace(nan_text.find("vertex 1 0 0"), 12, "vertex 1 nan 0");
  CHECK(has(error_of([&] { parse_stl(nan_text, "n.stl"); }), "n.stl:5: NaN y coordinate"));
  std::string two = text;
  two.erase(two.find("      vertex 0 1 0\n"), 19);
  CHECK(has(error_of([&] { parse_stl(two, "v.stl"); }), "v.stl:7: facet with 2 vertices"));
  CHECK(has(error_of([] { parse_stl("solid empty\nendsolid empty\n", "e.stl"); }), "e.stl: no vertices"));
}
