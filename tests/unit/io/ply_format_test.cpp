// SPDX-License-Identifier: MIT
#include "core/io/ply_format.h"

#include <cmath>
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

// Appends a value in little or big endian byte order.
template <typename T>
void put(std::string& out, T value, bool big_endian) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (big_endian)
    for (std::size_t k = 0; k < sizeof(T) / 2; ++k) std::swap(raw[k], raw[sizeof(T) - 1 - k]);
  out.append(raw, sizeof(T));
}

// A binary square (4 vertices, 1 quad) with mixed property types, an extra element and extra lists.
std::string binary_square(bool big_endian) {
  std::string out = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\ncomment mixed types\n"
                    "element vertex 4\nproperty uchar red\nproperty float x\nproperty double y\n"
                    "property list uchar short extra\nproperty short z\n"
                    "element face 1\nproperty int flags\nproperty list ushort uint vertex_index\n"
                    "element edge 1\nproperty int v1\nproperty int v2\nend_header\n";
  const float xs[4] = {0.f, 1.5f, 1.5f, 0.f};
  const double ys[4] = {0.0, 0.0, 0.1, 0.1};
  for (int v = 0; v < 4; ++v) {
    put<std::uint8_t>(out, 200, big_endian);
    put<float>(out, xs[v], big_endian);
    put<double>(out, ys[v], big_endian);
    put<std::uint8_t>(out, 2, big_endian);
    put<std::int16_t>(out, -1, big_endian);
    put<std::int16_t>(out, 7, big_endian);
    put<std::int16_t>(out, static_cast<std::int16_t>(-v), big_endian);
  }
  put<std::int32_t>(out, 42, big_endian);
  put<std::uint16_t>(out, 4, big_endian);
  for (std::uint32_t id : {0u, 1u, 2u, 3u}) put<std::uint32_t>(out, id, big_endian);
  put<std::int32_t>(out, 0, big_endian);
  put<std::int32_t>(out, 1, big_endian);
  return out;
}

const char* kAsciiHead =
    "ply\nformat ascii 1.0\ncomment c\nobj_info o\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

}  // namespace

TEST_CASE("ply: binary little and big endian with mixed types and skipped data") {
  for (bool big : {false, true}) {
    const auto m = parse_ply(binary_square(big), "s.ply");
    CHECK(m.num_vertices() == 4);
    REQUIRE(m.num_faces() == 2);
    CHECK(m.triangles.row(1) == Eigen::RowVector3i(0, 2, 3));
    CHECK(m.positions(1, 0) == 1.5);
    CHECK(m.positions(2, 1) == 0.1);  // double stays exact
    CHECK(m.positions(3, 2) == -3.0);
  }
}

TEST_CASE("ply: ascii with extra properties, CRLF header") {
  std::string text = kAsciiHead;
  text += "0 0 0 1\n1 0 0 2\n0 1 0.25 3\n3 0 1 2\n";
  auto m = parse_ply(text, "a.ply");
  CHECK(m.num_vertices() == 3);
  CHECK(m.num_faces() == 1);
  CHECK(m.positions(2, 2) == 0.25);
  std::string crlf;
  for (char c : text) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  m = parse_ply(crlf, "a.ply");
  CHECK(m.num_faces() == 1);
}

TEST_CASE("ply: binary little-endian round trip is exact and deterministic") {
  for (const auto& mesh : {volspline::test::tetrahedron(), volspline::test::cube()}) {
    const std::string bytes = serialize_ply(mesh);
    CHECK(has(bytes, "format binary_little_endian 1.0"));
    const auto back = parse_ply(bytes, "rt.ply");
    CHECK(back.positions == mesh.positions);
    CHECK(back.triangles == mesh.triangles);
    CHECK(serialize_ply(back) == bytes);
  }
}

TEST_CASE("ply: errors name the file and problem") {
  const std::string good = binary_square(false);
  const std::size_t data_start = good.find("end_header\n") + 11;
  // 64 bytes is the least that 4 vertices (lists empty) can take; these vertices take 80.
  CHECK(has(error_of([&] { parse_ply(good.substr(0, data_start + 78), "t.ply"); }),
            "t.ply: binary vertex data truncated at vertex 3 of 4"));
  CHECK(has(error_of([&] { parse_ply(good.substr(0, data_start + 85), "t.ply"); }),
            "t.ply: binary face data truncated at face 0 of 1"));
  CHECK(has(error_of([&] { parse_ply(good.substr(0, data_start + 30), "t.ply"); }),
            "t.ply: header claims 4 vertex elements but only 30 bytes of data follow"));
  CHECK(has(error_of([&] { parse_ply(good.substr(0, good.size() - 3), "t.ply"); }),
            "t.ply: binary edge data truncated at edge 0 of 1"));
  CHECK(has(error_of([&] { parse_ply(good.substr(0, data_start - 11), "h.ply"); }), "h.ply: truncated header"));

  const std::string head = kAsciiHead;
  CHECK(has(error_of([&] { parse_ply(head + "0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 1", "a.ply"); }),
            "a.ply: ascii face data truncated at face 0 of 1"));
  CHECK(has(error_of([&] { parse_ply(head + "0 0 0 1\n1 nan 0 2\n0 1 0 3\n3 0 1 2\n", "n.ply"); }),
            "n.ply: vertex 1: NaN y coordinate"));
  CHECK(has(error_of([&] { parse_ply(head + "0 0 0 1\n1 0 inf 2\n0 1 0 3\n3 0 1 2\n", "n.ply"); }),
            "n.ply: vertex 1: infinite z coordinate"));
  CHECK(has(error_of([&] { parse_ply(head + "0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 1 5\n", "i.ply"); }),
            "i.ply: face 0: index 5 out of range (3 vertices)"));
  CHECK(has(error_of([&] { parse_ply(head + "0 0 0 1\n1 0 0 2\n0 1 0 3\n2 0 1\n", "i.ply"); }),
            "i.ply: face 0 has 2 vertices"));
  CHECK(has(error_of([&] { parse_ply(head + "0 0 0 1\n1 0 0 2\n0 1 0 3\n2.2e22 0 1 2\n", "l.ply"); }),
            "l.ply: face 0: bad list length"));  // fuzz regression: huge ascii list length
  CHECK(has(error_of([&] { parse_ply(head + "0 0 0 1\n1 0 0 2\n0 1 0 3\n3.5 0 1 2\n", "l.ply"); }),
            "l.ply: face 0: bad list length"));
  CHECK(has(error_of([&] { parse_ply(head + "0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 1 x\n", "i.ply"); }),
            "i.ply:16: bad number 'x' in face 0"));

  std::string huge = kAsciiHead;
  huge.replace(huge.find("vertex 3"), 8, "vertex 1000000000000");
  CHECK(has(error_of([&] { parse_ply(huge + "0 0 0 1\n", "h.ply"); }),
            "h.ply: header claims 1000000000000 vertex elements but only 8 bytes of data follow"));
  std::string negative = kAsciiHead;
  negative.replace(negative.find("vertex 3"), 8, "vertex -3");
  CHECK(has(error_of([&] { parse_ply(negative, "c.ply"); }), "c.ply:5: negative count -3 for element 'vertex'"));
  std::string no_faces = kAsciiHead;
  no_faces.replace(no_faces.find("face 1"), 6, "face 0");
  CHECK(has(error_of([&] { parse_ply(no_faces + "0 0 0 1\n1 0 0 2\n0 1 0 3\n", "f.ply"); }), "f.ply: no faces"));
  std::string no_z = kAsciiHead;
  no_z.replace(no_z.find("float z"), 7, "float w");
  CHECK(has(error_of([&] { parse_ply(no_z, "z.ply"); }), "z.ply: vertex element lacks an x, y or z property"));

  CHECK(has(error_of([] { parse_ply("", "e.ply"); }), "e.ply: empty file"));
  CHECK(has(error_of([] { parse_ply("plx\n", "b.ply"); }), "b.ply:1: not a PLY file"));
  CHECK(has(error_of([] { parse_ply("ply\nformat binary_middle_endian 1.0\n", "b.ply"); }),
            "b.ply:2: unknown PLY format 'binary_middle_endian'"));
  CHECK(has(error_of([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n", "b.ply"); }),
            "b.ply:4: unknown property type 'quad'"));
  CHECK(has(error_of([] { parse_ply("ply\nformat ascii 1.0\nbogus\n", "b.ply"); }),
            "b.ply:3: unknown header keyword 'bogus'"));
  CHECK(has(error_of([] { parse_ply("ply\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n", "b.ply"); }),
            "b.ply:4: header has no format line"));
}
