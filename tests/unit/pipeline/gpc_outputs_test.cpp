// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "core/io/gpc_writers.h"
#include "core/pipeline/gpc_outputs.h"
#include "core/polycube/cuboid_layout.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

std::uint32_t u32_at(const std::string& s, std::size_t at) {
  std::uint32_t x = 0;
  std::memcpy(&x, s.data() + at, 4);
  return x;
}

}  // namespace

TEST_CASE("gpc outputs: a torus's one cuboid has 8 corners on its surface joined by 12 poly-edges") {
  const pipeline::GpcResult r = pipeline::run_gpc(test::torus(40, 16, 1.0, 0.35), "torus");
  REQUIRE(r.stats.cuboids == 1);
  const pipeline::GpcSegmentation s = pipeline::gpc_segmentation(r);
  REQUIRE(s.corners.size() == 8);
  REQUIRE(s.poly_edges.size() == 12);
  for (int e = 0; e < polycube::num_cube_edges; ++e) {
    const auto ends = polycube::cube_edge_corners(e);
    REQUIRE(s.poly_edges[e].size() >= 2);
    // Each poly-edge runs from its cube edge's first corner to its second (exact copies).
    CHECK((s.poly_edges[e].front() - s.corners[ends[0]]).norm() == 0.0);
    CHECK((s.poly_edges[e].back() - s.corners[ends[1]]).norm() == 0.0);
  }
  // Corners are vertices of the refined surface that the GLB shows.
  for (const Eigen::Vector3d& c : s.corners) {
    double nearest = 1e300;
    for (int v = 0; v < r.surface.num_vertices(); ++v)
      nearest = std::min(nearest, (r.surface.positions.row(v).transpose() - c).norm());
    CHECK(nearest <= 1e-12);
  }
}

TEST_CASE("gpc outputs: the segmented GLB has one coloured point per face corner and the poly-edges") {
  const pipeline::GpcResult r = pipeline::run_gpc(test::torus(40, 16, 1.0, 0.35), "torus");
  const std::string glb = pipeline::gpc_segmentation_glb(r);
  REQUIRE(glb.size() > 20);
  CHECK(glb.compare(0, 4, "glTF") == 0);
  CHECK(u32_at(glb, 8) == glb.size());
  const nlohmann::json j = nlohmann::json::parse(glb.substr(20, u32_at(glb, 12)));
  const auto& accessors = j["accessors"];
  const auto& primitives = j["meshes"][0]["primitives"];
  REQUIRE(primitives.size() == 3);  // triangles, poly-edges, corners
  CHECK(accessors[primitives[0]["attributes"]["POSITION"].get<int>()]["count"] == 3 * r.surface.num_faces());
  CHECK(accessors[primitives[0]["attributes"]["COLOR_0"].get<int>()]["count"] == 3 * r.surface.num_faces());
  std::size_t segments = 0;
  for (const auto& line : pipeline::gpc_segmentation(r).poly_edges) segments += line.size() - 1;
  CHECK(accessors[primitives[1]["attributes"]["POSITION"].get<int>()]["count"] == 2 * segments);
  CHECK(accessors[primitives[2]["attributes"]["POSITION"].get<int>()]["count"] == 8);
}

TEST_CASE("gpc outputs: the stats JSON names DESIGN.md's GPC measures") {
  const pipeline::GpcResult r = pipeline::run_gpc(test::torus(40, 16, 1.0, 0.35), "torus");
  const std::string text = pipeline::gpc_stats_json(r.stats, "torus.off");
  CHECK(text.back() == '\n');
  const nlohmann::json j = nlohmann::json::parse(text);
  CHECK(j["input"] == "torus.off");
  CHECK(j["genus"] == 1);
  CHECK(j["t_shapes"] == 0);
  CHECK(j["tubes"] == 1);
  CHECK(j["caps"] == 0);
  CHECK(j["cuboids"] == 1);
  CHECK(j["ill_points"] == 0);
  CHECK(j["flipped_triangles"] == 0);
  CHECK(j["grid_inverted_hexes"] == r.stats.grid_inverted_hexes);
  CHECK(j["grid_min_scaled_jacobian"].get<double>() == r.stats.grid_min_scaled_jacobian);
  for (const char* stage : {"validate", "decompose", "t_to_cube", "volumetric_map", "total"})
    CHECK_MESSAGE(j["times_s"].contains(stage), stage);
}

TEST_CASE("segment colours: components in [0.25, 0.95], consecutive ids distinct") {
  std::set<std::array<float, 3>> seen;
  for (int s = 0; s < 16; ++s) {
    const auto c = io::segment_colour(s);
    for (float x : c) CHECK((x >= 0.25f && x <= 0.95f));
    seen.insert(c);
  }
  CHECK(seen.size() == 16);
}
