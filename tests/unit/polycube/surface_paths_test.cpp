// SPDX-License-Identifier: MIT
#include "core/polycube/surface_paths.h"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "core/mesh/mesh_geometry.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

double path_length(const mesh::HalfedgeMesh& m, const std::vector<double>& length, const std::vector<int>& path) {
  double sum = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) sum += length[polycube::edge_between(m, path[i], path[i + 1])];
  return sum;
}

}  // namespace

TEST_CASE("guided paths are as short as Dijkstra's, with Euclidean and other edge lengths") {
  const auto m = mesh::HalfedgeMesh::build(test::torus(40, 24), "torus");
  const std::vector<double> euclidean = mesh::edge_lengths(m);
  // Lengths below and above the straight line: the bound must drop below 1.
  std::vector<double> varied = euclidean;
  for (std::size_t e = 0; e < varied.size(); ++e) varied[e] *= 0.5 + 0.4 * std::sin(double(e));
  std::vector<char> blocked(m.num_vertices(), 0);
  for (int v = 0; v < m.num_vertices(); v += 7) blocked[v] = 1;
  CHECK(polycube::straight_line_bound(m, euclidean) == doctest::Approx(1.0).epsilon(1e-12));
  const double varied_bound = polycube::straight_line_bound(m, varied);
  CHECK(varied_bound < 0.2);
  for (const std::vector<double>* length : std::vector<const std::vector<double>*>{&euclidean, &varied}) {
    const double bound = length == &euclidean ? polycube::straight_line_bound(m, euclidean) : varied_bound;
    for (int source = 1; source < m.num_vertices(); source += 97) {
      const int target = (source * 31 + 5) % m.num_vertices();
      if (blocked[source] || target == source) continue;
      const auto reference = polycube::restricted_path(m, *length, source, target, blocked, nullptr);
      const auto guided = polycube::guided_path(m, *length, bound, source, target, blocked, nullptr);
      REQUIRE(reference.size() >= 2);
      REQUIRE(guided.size() >= 2);
      CHECK(guided.front() == source);
      CHECK(guided.back() == target);
      for (std::size_t i = 1; i + 1 < guided.size(); ++i) CHECK(!blocked[guided[i]]);
      // Tolerance: the same edges summed in another order.
      CHECK(path_length(m, *length, guided) == doctest::Approx(path_length(m, *length, reference)).epsilon(1e-12));
    }
  }
  // No path: a target walled in by blocked vertices.
  std::vector<char> wall(m.num_vertices(), 0);
  const int target = 100;
  for (int h : m.vertex_outgoing(target)) wall[m.halfedge_vertex(h)] = 1;
  CHECK(polycube::guided_path(m, euclidean, 1.0, 0, target, wall, nullptr).empty());
}
