// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "core/mesh/graph_distance.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_geometry.h"
#include "tests/unit/common/test_meshes.h"

using volspline::mesh::GraphDistances;
using volspline::mesh::HalfedgeMesh;
using volspline::mesh::no_id;
namespace mesh = volspline::mesh;
namespace t = volspline::test;

TEST_CASE("single source on a unit grid: diagonal steps then straight ones") {
  const int nx = 4, ny = 3;
  const HalfedgeMesh m = HalfedgeMesh::build(t::flat_grid(nx, ny));
  const GraphDistances d = mesh::graph_distances(m, {0});
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const int v = j * (nx + 1) + i;
      const double expected = std::min(i, j) * std::sqrt(2.0) + std::abs(i - j);
      CHECK(d.distance[v] == doctest::Approx(expected).epsilon(1e-14));
      CHECK(d.nearest_source[v] == 0);
      // The path's edge lengths add up to the distance.
      const std::vector<int> path = mesh::graph_path(d, v);
      REQUIRE(!path.empty());
      CHECK(path.front() == 0);
      CHECK(path.back() == v);
      double length = 0.0;
      for (size_t k = 0; k + 1 < path.size(); ++k) {
        length += (m.vertex_position(path[k + 1]) - m.vertex_position(path[k])).norm();
      }
      CHECK(length == doctest::Approx(d.distance[v]).epsilon(1e-14));
    }
  }
  CHECK(d.predecessor[0] == no_id);
  CHECK(mesh::graph_path(d, 0) == std::vector<int>{0});
}

TEST_CASE("ties keep the smaller predecessor id") {
  // Hop counts (all lengths 1): vertex (2,1) = 7 is 2 hops from 0 via (1,0) = 1 or (1,1) = 6.
  const HalfedgeMesh m = HalfedgeMesh::build(t::flat_grid(4, 3));
  const GraphDistances d =
      mesh::graph_distances(m, {0}, std::vector<double>(m.num_edges(), 1.0));
  CHECK(d.distance[7] == 2.0);
  CHECK(d.predecessor[7] == 1);
  // Same answer on a second run.
  const GraphDistances again =
      mesh::graph_distances(m, {0}, std::vector<double>(m.num_edges(), 1.0));
  CHECK(again.predecessor == d.predecessor);
}

TEST_CASE("several sources: each vertex takes the nearest; duplicates keep the first index") {
  const HalfedgeMesh m = HalfedgeMesh::build(t::flat_grid(6, 1));
  const int last = m.num_vertices() - 1;
  const GraphDistances d = mesh::graph_distances(m, {last, 0, last});
  const GraphDistances from_first = mesh::graph_distances(m, {last});
  const GraphDistances from_second = mesh::graph_distances(m, {0});
  for (int v = 0; v < m.num_vertices(); ++v) {
    CHECK(d.distance[v] == std::min(from_first.distance[v], from_second.distance[v]));
    const int expected = from_first.distance[v] <= from_second.distance[v] ? 0 : 1;
    if (from_first.distance[v] != from_second.distance[v]) CHECK(d.nearest_source[v] == expected);
  }
  CHECK(d.nearest_source[last] == 0);
  CHECK(d.nearest_source[0] == 1);
}

TEST_CASE("other components are unreachable") {
  const HalfedgeMesh m = HalfedgeMesh::build(t::two_tetrahedra());
  const GraphDistances d = mesh::graph_distances(m, {0});
  for (int v = 4; v < 8; ++v) {
    CHECK(d.distance[v] == std::numeric_limits<double>::infinity());
    CHECK(d.predecessor[v] == no_id);
    CHECK(d.nearest_source[v] == -1);
    CHECK(mesh::graph_path(d, v).empty());
  }
  CHECK(d.distance[1] == 1.0);
}

TEST_CASE("no sources: everything unreachable") {
  const HalfedgeMesh m = HalfedgeMesh::build(t::tetrahedron());
  const GraphDistances d = mesh::graph_distances(m, {});
  for (double x : d.distance) CHECK(std::isinf(x));
}
