// SPDX-License-Identifier: MIT
#include "core/param/hex_min_quality.h"

#include <cmath>
#include <random>

#include <doctest/doctest.h>

#include "core/mesh/hex_quality.h"

using namespace volspline;

namespace {

// The hexes of an n³ node grid of unit steps, node i + n·(j + n·k), and its nodes.
struct QualityGrid {
  std::vector<std::array<int, 8>> hexes;
  mesh::Positions xyz;
};
QualityGrid quality_unit_grid(int n) {
  QualityGrid g;
  g.xyz.resize(n * n * n, 3);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) g.xyz.row(i + n * (j + n * k)) << i, j, k;
  for (int k = 0; k + 1 < n; ++k)
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        std::array<int, 8> hex;
        for (int q = 0; q < 8; ++q) hex[q] = (i + (q & 1)) + n * ((j + (q >> 1 & 1)) + n * (k + (q >> 2 & 1)));
        g.hexes.push_back(hex);
      }
  return g;
}

double grid_least(const QualityGrid& g) {
  double m = 1.0;
  for (const auto& hex : g.hexes) {
    std::array<Eigen::Vector3d, 8> x;
    for (int q = 0; q < 8; ++q) x[q] = g.xyz.row(hex[q]).transpose();
    m = std::min(m, mesh::hex_min_scaled_jacobian(x));
  }
  return m;
}

bool on_grid_boundary(int v, int n) {
  const int i = v % n, j = v / n % n, k = v / (n * n);
  return i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1;
}

// The n³ grid with its inner nodes moved by up to 0.3 per axis (seeded); fixed: its boundary.
QualityGrid jittered_grid(int n, unsigned seed, std::vector<char>& fixed) {
  QualityGrid g = quality_unit_grid(n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  fixed.assign(n * n * n, 0);
  for (int v = 0; v < n * n * n; ++v) {
    fixed[v] = on_grid_boundary(v, n);
    if (fixed[v]) continue;
    // One draw per statement: the order of a call's arguments is the compiler's choice.
    const double dx = jitter(rng);
    const double dy = jitter(rng);
    const double dz = jitter(rng);
    g.xyz.row(v) += Eigen::RowVector3d(dx, dy, dz);
  }
  return g;
}

}  // namespace

TEST_CASE("hex_scaled_jacobian: VTK's measure, the corners and the centre's principal axes") {
  std::array<Eigen::Vector3d, 8> x;
  for (int q = 0; q < 8; ++q) x[q] = Eigen::Vector3d(q & 1, q >> 1 & 1, q >> 2 & 1);
  CHECK(mesh::hex_scaled_jacobian(x) == 1.0);
  // A sheared box (x + 0.75 y): every corner and the centre have the columns' scaled Jacobian.
  for (int q = 0; q < 8; ++q) x[q](0) += 0.75 * x[q](1);
  CHECK(mesh::hex_scaled_jacobian(x) == doctest::Approx(1.0 / std::sqrt(1.0 + 0.75 * 0.75)).epsilon(1e-15));
}

TEST_CASE("raise_min_scaled_jacobian: the centre of 2×2×2 unit cubes pushed to a corner goes back") {
  QualityGrid g = quality_unit_grid(3);
  std::vector<char> fixed(27, 1);
  fixed[13] = 0;
  g.xyz.row(13) << 0.4, 0.5, 0.35;
  const double before = grid_least(g);
  REQUIRE(before < 0.5);
  param::MinQualityOptions options;
  options.target = 1.0;
  const param::MinQualityReport r = param::raise_min_scaled_jacobian(g.hexes, fixed, g.xyz, options);
  CHECK(r.min_before == doctest::Approx(before).epsilon(1e-15));
  // The only placement with every corner a right angle is the centre (1, 1, 1): the least value
  // is 1 there; the ascent reaches it to the step length it halves down to.
  CHECK(r.min_after > 0.99);
  CHECK((g.xyz.row(13) - Eigen::RowVector3d(1, 1, 1)).norm() < 0.05);
  CHECK(r.min_after == doctest::Approx(grid_least(g)).epsilon(1e-15));
  // Fixed nodes stay.
  QualityGrid reference = quality_unit_grid(3);
  for (int v = 0; v < 27; ++v)
    if (v != 13) CHECK(g.xyz.row(v) == reference.xyz.row(v));
}

TEST_CASE("raise_min_scaled_jacobian: raises a jittered grid, never lowers a folded one, same bytes twice") {
  const int n = 6;
  std::vector<char> fixed;
  QualityGrid g = jittered_grid(n, 7, fixed);
  QualityGrid folded = g;
  const double before = grid_least(g);
  REQUIRE(before > 0.0);
  REQUIRE(before < 0.3);
  // The longest hex edge at each node on entry: a move never stretches an edge at the moving node
  // past its bound (MinQualityOptions::max_edge; by default 3 times the node's entry value).
  auto longest_edges = [&](const QualityGrid& q) {
    std::vector<double> longest(q.xyz.rows(), 0.0);
    for (const auto& hex : q.hexes)
      for (int c = 0; c < 8; ++c)
        for (int a = 0; a < 3; ++a) {
          const double l = (q.xyz.row(hex[c]) - q.xyz.row(hex[c ^ (1 << a)])).norm();
          longest[hex[c]] = std::max(longest[hex[c]], l);
        }
    return longest;
  };
  const std::vector<double> entry = longest_edges(g);
  REQUIRE(param::longest_hex_edges(g.hexes, g.xyz) == entry);
  param::MinQualityOptions bounded;
  bounded.max_edge = entry;
  for (double& l : bounded.max_edge) l *= 1.2;
  QualityGrid tight = g;
  param::raise_min_scaled_jacobian(tight.hexes, fixed, tight.xyz, bounded);
  CHECK(grid_least(tight) > before);
  for (const auto& hex : tight.hexes)
    for (int c = 0; c < 8; ++c)
      for (int a = 0; a < 3; ++a) {
        const int u = hex[c], w = hex[c ^ (1 << a)];
        CHECK((tight.xyz.row(u) - tight.xyz.row(w)).norm() <= 1.2 * std::max(entry[u], entry[w]));
      }
  const param::MinQualityReport r = param::raise_min_scaled_jacobian(g.hexes, fixed, g.xyz);
  CHECK(r.min_before == before);
  CHECK(r.min_after > 0.3);
  CHECK(r.min_after == grid_least(g));
  // Each edge was last changed by a move of one of its ends, bounded by that end's entry value.
  for (const auto& hex : g.hexes)
    for (int c = 0; c < 8; ++c)
      for (int a = 0; a < 3; ++a) {
        const int u = hex[c], w = hex[c ^ (1 << a)];
        CHECK((g.xyz.row(u) - g.xyz.row(w)).norm() <= 3.0 * std::max(entry[u], entry[w]));
      }
  // One node pushed through its neighbour: folded hexes. Moving one node at a time does not
  // untangle in general (that is untangle_hex_mesh's work), but the least value never falls.
  folded.xyz.row(2 + n * (2 + n * 2)) = folded.xyz.row(3 + n * (2 + n * 2)) + Eigen::RowVector3d(0.3, 0.0, 0.0);
  QualityGrid again = folded;
  const param::MinQualityReport f = param::raise_min_scaled_jacobian(folded.hexes, fixed, folded.xyz);
  CHECK(f.min_before < 0.0);
  CHECK(f.min_after >= f.min_before);
  param::raise_min_scaled_jacobian(again.hexes, fixed, again.xyz);
  CHECK(again.xyz == folded.xyz);
}

TEST_CASE("raise_min_scaled_jacobian: the barrier mode lifts the poor hexes together, above its floor") {
  const int n = 6;
  std::vector<char> fixed;
  QualityGrid g = jittered_grid(n, 3, fixed);
  const double before = grid_least(g);
  REQUIRE(before > 0.0);
  param::MinQualityOptions options;
  options.target = 0.6;
  options.barrier = 0.5;
  options.max_sweeps = 10;
  QualityGrid again = g;
  const param::MinQualityReport r = param::raise_min_scaled_jacobian(g.hexes, fixed, g.xyz, options);
  CHECK(r.min_before == before);
  CHECK(r.moves > 0);
  // Every corner below target pulls: fewer hexes stay below it; none falls to the floor.
  CHECK(r.below_after < r.below_before);
  CHECK(grid_least(g) > before - 0.5 * (0.6 - before));
  // Followed by the greedy ascent from there.
  options.barrier = 0.0;
  options.max_sweeps = 60;
  const param::MinQualityReport greedy = param::raise_min_scaled_jacobian(g.hexes, fixed, g.xyz, options);
  CHECK(greedy.min_after > before);
  param::MinQualityOptions barrier = options;
  barrier.barrier = 0.5;
  barrier.max_sweeps = 10;
  param::raise_min_scaled_jacobian(again.hexes, fixed, again.xyz, barrier);
  param::raise_min_scaled_jacobian(again.hexes, fixed, again.xyz, options);
  CHECK(again.xyz == g.xyz);  // deterministic
}

TEST_CASE("raise_min_scaled_jacobian: sliding nodes stay on their surface") {
  // A 4³ grid whose bottom face z = 0 slides on the plane z = 0 with its nodes sheared in x.
  const int n = 4;
  QualityGrid g = quality_unit_grid(n);
  std::vector<char> fixed(n * n * n, 0);
  param::SlidingNodes sliding;
  sliding.slides.assign(n * n * n, 0);
  for (int v = 0; v < n * n * n; ++v) {
    const int i = v % n, j = v / n % n, k = v / (n * n);
    const bool bottom = k == 0, side = i == 0 || j == 0 || i == n - 1 || j == n - 1 || k == n - 1;
    fixed[v] = side && !(bottom && i > 0 && j > 0 && i < n - 1 && j < n - 1);
    sliding.slides[v] = !fixed[v] && bottom;
    if (bottom && !fixed[v]) g.xyz(v, 0) += 0.7 * (j - 1);
  }
  sliding.project = [](int, const Eigen::Vector3d& p, Eigen::Matrix3d* tangent) {
    if (tangent) *tangent = Eigen::Vector3d(1, 1, 0).asDiagonal();
    return Eigen::Vector3d(p.x(), p.y(), 0.0);
  };
  const double before = grid_least(g);
  param::MinQualityOptions options;
  options.target = 1.0;
  const param::MinQualityReport r = param::raise_min_scaled_jacobian(g.hexes, fixed, g.xyz, options, &sliding);
  // Unsheared, every hex is a unit cube.
  CHECK(before < 0.7);
  CHECK(r.min_after > 0.95);
  for (int v = 0; v < n * n; ++v) CHECK(g.xyz(v, 2) == 0.0);
}

TEST_CASE("raise_min_scaled_jacobian: bad options and cancellation") {
  QualityGrid g = quality_unit_grid(3);
  std::vector<char> fixed(27, 0);
  param::MinQualityOptions bad;
  bad.max_sweeps = 0;
  CHECK_THROWS_WITH_AS(param::raise_min_scaled_jacobian(g.hexes, fixed, g.xyz, bad), doctest::Contains("max_sweeps"),
                       Error);
  g.xyz.row(13) << 0.4, 0.5, 0.35;
  const Progress stop([](const std::string& stage, double) { return stage != "grid quality"; });
  CHECK_THROWS_AS(param::raise_min_scaled_jacobian(g.hexes, fixed, g.xyz, {}, nullptr, stop), Cancelled);
}
