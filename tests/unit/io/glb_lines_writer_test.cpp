// SPDX-License-Identifier: MIT
#include "core/io/glb_lines_writer.h"

#include <cstdint>
#include <cstring>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "core/io/textured_glb_writer.h"
#include "core/spline/bspline_volume.h"

using namespace volspline;

namespace {

std::uint32_t u32(const std::string& s, std::size_t at) {
  std::uint32_t x = 0;
  for (int i = 0; i < 4; ++i) x |= std::uint32_t(static_cast<unsigned char>(s[at + i])) << (8 * i);
  return x;
}

// The identity map of the unit cube as a cubic T-spline.
spline::TSpline unit_cube_spline() {
  const std::vector<double> knots = spline::boundary_restricted_knots({0.0, 1.0});
  Eigen::MatrixXd points(64, 3);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) points.row(i + 4 * (j + 4 * k)) << i / 3.0, j / 3.0, k / 3.0;
  return spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points));
}

}  // namespace

TEST_CASE("glb preview: header, chunks and the two primitives") {
  const spline::TSpline ts = unit_cube_spline();
  const std::string glb = io::serialize_spline_glb(ts, 5, 3);
  REQUIRE(glb.size() > 20);
  CHECK(glb.substr(0, 4) == "glTF");
  CHECK(u32(glb, 4) == 2);
  CHECK(u32(glb, 8) == glb.size());
  const std::uint32_t json_length = u32(glb, 12);
  CHECK(u32(glb, 16) == 0x4E4F534A);
  const auto gltf = nlohmann::json::parse(glb.substr(20, json_length));
  CHECK(gltf["meshes"][0]["primitives"].size() == 2);
  CHECK(gltf["meshes"][0]["primitives"][1]["mode"] == 1);
  CHECK(gltf["accessors"][0]["count"] == 6 * 25);
  CHECK(gltf["accessors"][1]["count"] == 6 * 2 * 16 * 3);
  CHECK(gltf["accessors"][0]["max"][0].get<double>() == doctest::Approx(1.0));
  CHECK(u32(glb, 20 + json_length) + 28 + json_length == glb.size());
}

TEST_CASE("glb preview: unit outward normals on the unit cube's boundary, one default scene") {
  const spline::TSpline ts = unit_cube_spline();
  const std::string glb = io::serialize_spline_glb(ts, 5, 3);
  const std::uint32_t json_length = u32(glb, 12);
  const auto gltf = nlohmann::json::parse(glb.substr(20, json_length));
  CHECK(gltf["scene"] == 0);
  const auto& attributes = gltf["meshes"][0]["primitives"][0]["attributes"];
  REQUIRE(attributes.contains("NORMAL"));
  const int position_id = attributes["POSITION"], normal_id = attributes["NORMAL"];
  const std::size_t bin = 20 + json_length + 8;
  auto view_of = [&](int accessor) {
    const auto& view = gltf["bufferViews"][gltf["accessors"][accessor]["bufferView"].get<int>()];
    return bin + view["byteOffset"].get<std::size_t>();
  };
  const std::size_t count = gltf["accessors"][normal_id]["count"];
  CHECK(count == gltf["accessors"][position_id]["count"]);
  for (std::size_t v = 0; v < count; ++v) {
    float p[3], n[3];
    std::memcpy(p, glb.data() + view_of(position_id) + 12 * v, 12);
    std::memcpy(n, glb.data() + view_of(normal_id) + 12 * v, 12);
    const Eigen::Vector3f position(p[0], p[1], p[2]), normal(n[0], n[1], n[2]);
    CHECK(normal.norm() == doctest::Approx(1.0).epsilon(1e-6));
    // Outward on a cube centred at 0.5: the normal points away from the centre.
    CHECK(normal.dot(position - Eigen::Vector3f::Constant(0.5f)) > 0);
  }
}

TEST_CASE("textured lens GLB: y up, UVs over the image, the PNG embedded, triangles facing +z") {
  io::TexturedPlane plane;
  plane.positions.resize(3, 2);
  plane.positions << 0, 0, 10, 0, 0, 10;  // pixels, y down: positive signed area
  plane.texture = plane.positions;
  plane.triangles.resize(1, 3);
  plane.triangles << 0, 1, 2;
  plane.output_height = 20;
  plane.texture_width = 40;
  plane.texture_height = 20;
  plane.texture_png = std::string("\x89PNG\r\n\x1a\n", 8) + "not a real image";
  const std::string glb = io::serialize_textured_glb(plane);
  const std::uint32_t json_length = u32(glb, 12);
  const auto gltf = nlohmann::json::parse(glb.substr(20, json_length));
  const auto& primitive = gltf["meshes"][0]["primitives"][0];
  CHECK(primitive["attributes"].contains("TEXCOORD_0"));
  CHECK(gltf["images"][0]["mimeType"] == "image/png");
  CHECK(gltf["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] == 0);
  const std::size_t bin = 20 + json_length + 8;
  auto offset = [&](int accessor) {
    return bin + gltf["bufferViews"][gltf["accessors"][accessor]["bufferView"].get<int>()]["byteOffset"].get<std::size_t>();
  };
  float xyz[9], uv[6];
  std::uint32_t index[3];
  std::memcpy(xyz, glb.data() + offset(primitive["attributes"]["POSITION"]), sizeof xyz);
  std::memcpy(uv, glb.data() + offset(primitive["attributes"]["TEXCOORD_0"]), sizeof uv);
  std::memcpy(index, glb.data() + offset(primitive["indices"]), sizeof index);
  CHECK(xyz[1] == 20.0f);  // pixel row 0 is the top: y = height
  CHECK(xyz[7] == 10.0f);
  CHECK(uv[2] == 0.25f);   // 10 / 40
  CHECK(uv[5] == 0.5f);    // row 10 of 20, glTF's v runs down
  // Counter-clockwise seen from +z in the y-up frame.
  const Eigen::Vector2f a(xyz[3 * index[0]], xyz[3 * index[0] + 1]), b(xyz[3 * index[1]], xyz[3 * index[1] + 1]),
      c(xyz[3 * index[2]], xyz[3 * index[2] + 1]);
  CHECK((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x() > 0);
  const auto& view = gltf["bufferViews"][gltf["images"][0]["bufferView"].get<int>()];
  CHECK(glb.substr(bin + view["byteOffset"].get<std::size_t>(), view["byteLength"].get<std::size_t>()) == plane.texture_png);
}
