// SPDX-License-Identifier: MIT
#include "core/param/hex_grid_untangling.h"

#include <array>
#include <string>
#include <vector>

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

// The hexes of the n×n×n node lattice as a hex list (node q at offset (q&1, q>>1&1, q>>2&1)).
std::vector<std::array<int, 8>> grid_hexes(int n) {
  std::vector<std::array<int, 8>> hexes;
  for (int k = 0; k + 1 < n; ++k)
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        std::array<int, 8> hex;
        for (int q = 0; q < 8; ++q) hex[q] = param::grid_node_index({n, n, n}, i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1));
        hexes.push_back(hex);
      }
  return hexes;
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

TEST_CASE("hex grid untangling reports its steps and stops when asked") {
  const int n = 5;
  std::vector<char> fixed;
  mesh::Positions folded = lattice(n, fixed);
  folded(param::grid_node_index({n, n, n}, 1, 2, 2), 0) = 0.8;
  // Every step reports "grid untangling" with a fraction of rounds × max_steps, increasing.
  std::vector<double> fractions;
  const Progress record([&fractions](const std::string& stage, double fraction) {
    CHECK(stage == "grid untangling");
    fractions.push_back(fraction);
    return true;
  });
  mesh::Positions xyz = folded;
  const param::HexGridUntangleOptions options;
  const param::HexGridUntangleReport report = param::untangle_hex_grid({n, n, n}, fixed, xyz, options, record);
  CHECK(report.final_inverted == 0);
  REQUIRE(!fractions.empty());
  CHECK(fractions.front() == 0.0);
  for (std::size_t i = 1; i < fractions.size(); ++i) CHECK(fractions[i] > fractions[i - 1]);
  CHECK(fractions.back() < 1.0);
  // The same grid as hexes of a mesh, cancelled at the second step: Cancelled, the fixed nodes kept.
  const std::vector<std::array<int, 8>> hexes = grid_hexes(n);
  int reports = 0;
  const Progress stop([&reports](const std::string&, double) { return ++reports < 2; });
  xyz = folded;
  CHECK_THROWS_AS(param::untangle_hex_mesh(hexes, fixed, xyz, {}, options, nullptr, stop), Cancelled);
  CHECK(reports == 2);
  for (int id = 0; id < n * n * n; ++id)
    if (fixed[id]) CHECK(xyz.row(id) == folded.row(id));
}

TEST_CASE("hex mesh untangling with each hex's own reference cell unfolds a fold among hexes a thousand times smaller") {
  // Per axis the nodes 0, 0.001, 0.002, 0.003, 0.5, 1: tiny cubes at one corner of the unit cube
  // beside hexes 500 times longer; the boundary held.
  const std::array<double, 6> t = {0.0, 0.001, 0.002, 0.003, 0.5, 1.0};
  const int n = 6;
  mesh::Positions xyz(n * n * n, 3);
  std::vector<char> fixed(n * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int id = param::grid_node_index({n, n, n}, i, j, k);
        xyz.row(id) << t[i], t[j], t[k];
        fixed[id] = i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1;
      }
  const std::vector<std::array<int, 8>> hexes = grid_hexes(n);
  // Node (2, 2, 2) pushed past (3, 2, 2).
  xyz(param::grid_node_index({n, n, n}, 2, 2, 2), 0) = 0.0035;
  REQUIRE(min_hex_quality(n, xyz) < 0.0);
  // The mean cell's barrier hardly sees the tiny hexes' determinants: it opens the fold to a
  // least scaled Jacobian of a few 1e-6; each hex's own cell opens it hundreds of times wider.
  std::array<double, 2> least{};
  for (int r = 0; r < 2; ++r) {
    mesh::Positions moved = xyz;
    param::HexGridUntangleOptions options;
    options.reference = r == 0 ? param::HexGridUntangleOptions::Reference::MeanCell
                               : param::HexGridUntangleOptions::Reference::OwnCell;
    const param::HexGridUntangleReport report = param::untangle_hex_mesh(hexes, fixed, moved, {}, options);
    CHECK(report.initial_inverted > 0);
    CHECK(report.final_inverted == 0);
    least[r] = min_hex_quality(n, moved);
    CHECK(least[r] > 0.0);
    for (int id = 0; id < n * n * n; ++id)
      if (fixed[id]) CHECK(moved.row(id) == xyz.row(id));
  }
  CHECK(least[1] > 100.0 * least[0]);
}
