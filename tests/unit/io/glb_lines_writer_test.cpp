// SPDX-License-Identifier: MIT
#include "core/io/glb_lines_writer.h"

#include <cstdint>
#include <cstring>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "core/spline/bspline_volume.h"

using namespace volspline;

namespace {

std::uint32_t u32(const std::string& s, std::size_t at) {
  std::uint32_t x = 0;
  for (int i = 0; i < 4; ++i) x |= std::uint32_t(static_cast<unsigned char>(s[at + i])) << (8 * i);
  return x;
}

}  // namespace

TEST_CASE("glb preview: header, chunks and the two primitives") {
  const std::vector<double> knots = spline::boundary_restricted_knots({0.0, 1.0});
  Eigen::MatrixXd points(64, 3);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) points.row(i + 4 * (j + 4 * k)) << i / 3.0, j / 3.0, k / 3.0;
  const spline::TSpline ts = spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points));
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
