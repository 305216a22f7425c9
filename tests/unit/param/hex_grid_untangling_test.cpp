// SPDX-License-Identifier: MIT
#include "core/param/hex_grid_untangling.h"

#include <doctest/doctest.h>

#include "core/mesh/hex_quality.h"

#include "core/param/volumetric_grid_map.h"

using namespace volspline;

namespace {

// The uniform n×n×n node lattice of the unit cube and its boundary flags.
mesh::Positions lattice(int n, std::vector<char>& fixed) {
  mesh::Positions xyz(n * n * n, 3);
  fixed.assign(n * n * n, 0);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int id = param::grid_node_index({n, n, n}, i, j, k);
        xyz.row(id) << double(i) / (n - 1), double(j) / (n - 1), double(k) / (n - 1);
        fixed[id] = i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1;
      }
  return xyz;
}

double min_hex_quality(int n, const mesh::Positions& xyz) {
  double worst = 1.0;
  for (int k = 0; k + 1 < n; ++k)
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        std::array<Eigen::Vector3d, 8> x;
        for (int c = 0; c < 8; ++c)
          x[c] = xyz.row(param::grid_node_index({n, n, n}, i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))).transpose();
        worst = std::min(worst, mesh::hex_min_scaled_jacobian(x));
      }
  return worst;
}

}  // namespace

TEST_CASE("hex grid untangling unfolds a node pushed past its neighbours and keeps the boundary") {
  const int n = 5;
  std::vector<char> fixed;
  mesh::Positions xyz = lattice(n, fixed);
  const mesh::Positions boundary = xyz;
  // Node (1, 2, 2) at x = 0.25 pushed to x = 0.8, beyond nodes (2, 2, 2) and (3, 2, 2).
  xyz(param::grid_node_index({n, n, n}, 1, 2, 2), 0) = 0.8;
  REQUIRE(min_hex_quality(n, xyz) < 0.0);
  const param::HexGridUntangleReport report = param::untangle_hex_grid({n, n, n}, fixed, xyz);
  CHECK(report.initial_inverted > 0);
  CHECK(report.final_inverted == 0);
  CHECK(report.free_nodes > 0);
  CHECK(min_hex_quality(n, xyz) > 0.0);
  for (int id = 0; id < n * n * n; ++id)
    if (fixed[id]) CHECK(xyz.row(id) == boundary.row(id));
}

TEST_CASE("hex grid untangling leaves a valid grid alone") {
  const int n = 4;
  std::vector<char> fixed;
  mesh::Positions xyz = lattice(n, fixed);
  const mesh::Positions before = xyz;
  const param::HexGridUntangleReport report = param::untangle_hex_grid({n, n, n}, fixed, xyz);
  CHECK(report.initial_inverted == 0);
  CHECK(report.iterations == 0);
  CHECK(xyz == before);
}

TEST_CASE("hex grid untangling gives up on a fold no interior placement can open, early and deterministically") {
  const int n = 4;
  std::vector<char> fixed;
  const mesh::Positions start = [&] {
    mesh::Positions xyz = lattice(n, fixed);
    // Boundary node (0, 1, 1) pushed beyond the opposite face x = 1: its corners need interior
    // nodes beyond x = 1.5 while their hexes' other corners need them below the fixed x = 1.
    xyz(param::grid_node_index({n, n, n}, 0, 1, 1), 0) = 1.5;
    return xyz;
  }();
  mesh::Positions xyz = start;
  const param::HexGridUntangleReport report = param::untangle_hex_grid({n, n, n}, fixed, xyz);
  CHECK(report.initial_inverted > 0);
  CHECK(report.final_inverted > 0);
  // Stopped by the stall rules, long before max_steps · max_inner = 1200 iterations per round.
  CHECK(report.iterations < 400);
  for (int id = 0; id < n * n * n; ++id)
    if (fixed[id]) CHECK(xyz.row(id) == start.row(id));
  mesh::Positions again = start;
  param::untangle_hex_grid({n, n, n}, fixed, again);
  CHECK(again == xyz);
}
