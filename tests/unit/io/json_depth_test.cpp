// SPDX-License-Identifier: MIT
#include "core/io/json_depth.h"

#include <string>

#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/io/mesh_io.h"

using namespace volspline;

namespace {

int depth_of(const std::string& text) { return io::json_nesting_depth(text.data(), text.size()); }

std::string nested_gltf(int depth) {
  return R"({"asset":{"version":"2.0"},"extras":)" + std::string(depth, '[') + std::string(depth, ']') + "}";
}

}  // namespace

TEST_CASE("json_nesting_depth counts arrays and objects, not brackets inside strings") {
  CHECK(depth_of("") == 0);
  CHECK(depth_of("1") == 0);
  CHECK(depth_of("[]") == 1);
  CHECK(depth_of(R"({"a":[{"b":[]}],"c":{}})") == 4);
  CHECK(depth_of(R"(["[[[[", "\"[[[", {}])") == 2);
  CHECK(depth_of("]]]][") == 1);
  CHECK(depth_of(std::string(20000, '[')) == 20000);
}

TEST_CASE("a glTF nesting deeper than 512 levels is refused before tinygltf parses it") {
  CHECK_THROWS_WITH_AS(io::parse_mesh(nested_gltf(20000), io::MeshFormat::Gltf, "deep.gltf"),
                       "deep.gltf: JSON nests deeper than 512 levels", Error);
  // At the limit the parser runs (and refuses the file for having no mesh, not for its depth).
  try {
    io::parse_mesh(nested_gltf(io::kMaxJsonDepth - 1), io::MeshFormat::Gltf, "ok.gltf");
    FAIL("a glTF without meshes parsed");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find("nests deeper") == std::string::npos);
  }
}

TEST_CASE("a deeply nested GLB JSON chunk is refused") {
  std::string json = nested_gltf(20000);
  while (json.size() % 4) json += ' ';
  std::string glb = "glTF";
  auto put32 = [&glb](std::uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
  put32(2);
  put32(static_cast<std::uint32_t>(20 + json.size()));
  put32(static_cast<std::uint32_t>(json.size()));
  put32(0x4E4F534Au);
  glb += json;
  CHECK_THROWS_WITH_AS(io::parse_mesh(glb, io::MeshFormat::Gltf, "deep.glb"),
                       "deep.glb: JSON nests deeper than 512 levels", Error);
}

TEST_CASE("a deeply nested spline JSON is refused") {
  CHECK_THROWS_WITH_AS(io::check_json_depth(std::string(600, '{').data(), 600, "spline 's.json'"),
                       "spline 's.json': JSON nests deeper than 512 levels", Error);
}
