// SPDX-License-Identifier: MIT
#include "core/io/gltf_format.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <map>

#include "core/io/file_bytes.h"
#include "core/io/mesh_io.h"
#include "tests/unit/common/test_meshes.h"
#include "tests/unit/io/io_test_util.h"

using namespace volspline::io;
using volspline::io::test::error_of;
using volspline::io::test::has;

namespace {

std::string base64(const std::string& bytes) {
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t n = (std::uint32_t(std::uint8_t(bytes[i])) << 16) | (std::uint32_t(std::uint8_t(bytes[i + 1])) << 8) |
                            std::uint8_t(bytes[i + 2]);
    for (int k = 3; k >= 0; --k) out += kDigits[(n >> (6 * k)) & 63];
  }
  if (i < bytes.size()) {
    std::uint32_t n = std::uint32_t(std::uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) n |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
    out += kDigits[(n >> 18) & 63];
    out += kDigits[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kDigits[(n >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

template <typename T>
void put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

// A .gltf with an embedded buffer: a triangle mesh (uint8 indices) used by two nodes, the second
// a child translated by (10,0,0) and mirrored in x, plus a POINTS primitive that must be skipped.
nlohmann::json two_instances() {
  std::string bin;
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(bin, v);
  for (std::uint8_t i : {0, 1, 2}) put(bin, i);
  bin.append(3, '\0');
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}, {"children", {1}}}, {{"mesh", 0}, {"translation", {10, 0, 0}}, {"scale", {-1, 1, 1}}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}, {{"attributes", {{"POSITION", 0}}}, {"mode", 0}}}}}}},
      {"accessors",
       {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
        {{"bufferView", 1}, {"componentType", 5121}, {"count", 3}, {"type", "SCALAR"}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}}, {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 3}}}},
      {"buffers", {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}}}};
  return j;
}

}  // namespace

TEST_CASE("gltf: all instances with node transforms, points skipped, mirror keeps orientation") {
  const auto m = parse_gltf(two_instances().dump(), "two.gltf");
  CHECK(m.num_vertices() == 6);
  REQUIRE(m.num_faces() == 2);
  CHECK(m.triangles.row(0) == Eigen::RowVector3i(0, 1, 2));
  CHECK(m.positions.row(4) == Eigen::RowVector3d(9, 0, 0));
  CHECK(m.triangles.row(1) == Eigen::RowVector3i(3, 5, 4));  // mirrored instance flipped back
}

TEST_CASE("gltf: GLB round trip through tinygltf, with POSITION min/max") {
  for (const auto& mesh : {volspline::test::tetrahedron(), volspline::test::cube(0.25, 2.0)}) {
    const std::string glb = serialize_glb(mesh);
    CHECK(glb.compare(0, 4, "glTF") == 0);
    CHECK(glb.size() % 4 == 0);
    CHECK(serialize_glb(mesh) == glb);
    const auto back = parse_gltf(glb, "rt.glb");
    CHECK(back.positions == mesh.positions);  // exact: these coordinates are float32 values
    CHECK(back.triangles == mesh.triangles);
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    const auto j = nlohmann::json::parse(glb.substr(20, json_length));
    CHECK(j["accessors"][0]["min"] == nlohmann::json({mesh.positions.col(0).minCoeff(), mesh.positions.col(1).minCoeff(),
                                                      mesh.positions.col(2).minCoeff()}));
    CHECK(j["accessors"][0]["max"][0] == mesh.positions.col(0).maxCoeff());
  }
  // Non-float values are rounded to float32: relative error at most 2^-24.
  const auto cube = volspline::test::cube(0.1);
  const auto back = parse_gltf(serialize_glb(cube), "c.glb");
  CHECK((back.positions - cube.positions).cwiseAbs().maxCoeff() <= 1.2 * std::ldexp(1.0, -24));
}

TEST_CASE("gltf: errors name the file and problem") {
  auto j = two_instances();
  j["accessors"][1]["count"] = 4;
  CHECK(has(error_of([&] { parse_gltf(j.dump(), "c.gltf"); }), "c.gltf: mesh 0 primitive 0 indices: accessor 1: 4 elements do not fit"));
  j = two_instances();
  j["accessors"][0]["count"] = 2;
  CHECK(has(error_of([&] { parse_gltf(j.dump(), "r.gltf"); }), "r.gltf: mesh 0 primitive 0: index 2 out of range (2 vertices)"));
  j = two_instances();
  j["nodes"][1]["children"] = {0};
  CHECK(has(error_of([&] { parse_gltf(j.dump(), "y.gltf"); }), "y.gltf: node 0 is reached twice"));
  j = two_instances();
  j["nodes"][1]["scale"] = {1e308, 1e308, 1e308};
  j["nodes"][1]["translation"] = {1e308, 0, 0};
  CHECK(has(error_of([&] { parse_gltf(j.dump(), "f.gltf"); }), "f.gltf: mesh 0 primitive 0: vertex 1 has a NaN or infinite"));
  j = two_instances();
  j["buffers"][0]["uri"] = "external.bin";
  CHECK(has(error_of([&] { parse_gltf(j.dump(), "x.gltf"); }), "x.gltf: invalid glTF"));
  j = two_instances();
  j["meshes"][0]["primitives"][0]["mode"] = 1;
  CHECK(has(error_of([&] { parse_gltf(j.dump(), "p.gltf"); }), "p.gltf: no faces"));
  CHECK(has(error_of([] { parse_gltf("{ not json", "b.gltf"); }), "b.gltf: invalid glTF"));
  CHECK(has(error_of([] { parse_gltf("", "e.gltf"); }), "e.gltf: empty file"));
  const std::string glb = serialize_glb(volspline::test::tetrahedron());
  CHECK(has(error_of([&] { parse_gltf(glb.substr(0, glb.size() - 8), "t.glb"); }), "t.glb: invalid glTF"));
}

TEST_CASE("gltf: a non-indexed primitive's coincident corners are welded into a closed mesh") {
  const std::string dir = VOLSPLINE_SOURCE_DIR "/tests/data/meshes/";
  const volspline::mesh::TriangleMesh tet = read_mesh(dir + "tetra_unindexed.gltf");
  CHECK(tet.num_vertices() == 4);
  CHECK(tet.num_faces() == 4);
  // Every edge shared by exactly two triangles: the mesh is closed.
  std::map<std::pair<int, int>, int> edges;
  for (int f = 0; f < tet.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = tet.triangles(f, k), b = tet.triangles(f, (k + 1) % 3);
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  CHECK(edges.size() == 6);
  for (const auto& [edge, count] : edges) CHECK(count == 2);
}

TEST_CASE("gltf: Draco and meshopt compressed meshes are refused naming the extension") {
  const std::string dir = VOLSPLINE_SOURCE_DIR "/tests/data/meshes/";
  CHECK(has(error_of([&] { read_mesh(dir + "draco_flagged.gltf"); }),
                      "draco_flagged.gltf: meshes compressed with KHR_draco_mesh_compression are not supported"));
  const std::string meshopt = read_file_bytes(dir + "tetra_unindexed.gltf");
  const std::string flagged = "{\"extensionsUsed\":[\"EXT_meshopt_compression\"]," + meshopt.substr(1);
  CHECK(has(error_of([&] { parse_gltf(flagged, "m.gltf"); }),
                      "m.gltf: meshes compressed with EXT_meshopt_compression are not supported"));
}
