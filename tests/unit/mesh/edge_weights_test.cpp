// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>

#include "core/mesh/edge_weights.h"
#include "core/mesh/halfedge_mesh.h"
#include "tests/unit/common/test_meshes.h"

using volspline::mesh::HalfedgeMesh;
using volspline::mesh::TriangleMesh;
namespace mesh = volspline::mesh;
namespace t = volspline::test;

namespace {

/// Σ_j w_ij (x_j − x_i) over the one-ring of v: zero for weights with linear precision.
Eigen::Vector3d weighted_ring_sum(const HalfedgeMesh& m, const std::vector<double>& halfedge_w,
                                  int v) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int h : m.vertex_outgoing(v)) {
    sum += halfedge_w[h] * (m.vertex_position(m.halfedge_vertex(h)) - m.vertex_position(v));
  }
  return sum;
}

}  // namespace

TEST_CASE("cotan weights of single triangles (boundary edges are one-sided)") {
  SUBCASE("equilateral: cot 60° / 2 on every edge") {
    const HalfedgeMesh m = HalfedgeMesh::build(
        t::make_mesh({0, 0, 0, 1, 0, 0, 0.5, std::sqrt(3.0) / 2, 0}, {0, 1, 2}));
    for (double w : mesh::cotan_weights(m)) CHECK(w == doctest::Approx(0.5 / std::sqrt(3.0)).epsilon(1e-14));
  }
  SUBCASE("right isosceles: 0 opposite the right angle, 1/2 elsewhere") {
    const HalfedgeMesh m = HalfedgeMesh::build(t::make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}));
    const std::vector<double> w = mesh::cotan_weights(m);
    // Edges in order (0,1), (0,2), (1,2).
    CHECK(w[0] == doctest::Approx(0.5).epsilon(1e-14));
    CHECK(w[1] == doctest::Approx(0.5).epsilon(1e-14));
    CHECK(std::abs(w[2]) < 1e-15);
  }
  SUBCASE("obtuse pair gives a negative weight") {
    // Two triangles over edge (0, 1) with apexes close to it: both opposite angles > 90°.
    const HalfedgeMesh m = HalfedgeMesh::build(
        t::make_mesh({0, 0, 0, 2, 0, 0, 1, 0.2, 0, 1, -0.2, 0}, {0, 1, 2, 1, 0, 3}));
    CHECK(mesh::cotan_weights(m)[0] < 0.0);
  }
}

TEST_CASE("cotan weights are scale invariant and sum interior edges from both sides") {
  const TriangleMesh small = t::torus(9, 6);
  TriangleMesh big = small;
  big.positions *= 1000.0;
  const std::vector<double> a = mesh::cotan_weights(HalfedgeMesh::build(small));
  const std::vector<double> b = mesh::cotan_weights(HalfedgeMesh::build(big));
  REQUIRE(a.size() == b.size());
  for (size_t e = 0; e < a.size(); ++e) CHECK(b[e] == doctest::Approx(a[e]).epsilon(1e-12));
}

TEST_CASE("cotan and mean-value weights reproduce linear functions on a flat interior") {
  const HalfedgeMesh m = HalfedgeMesh::build(t::flat_grid(6, 5, 0.25));
  const std::vector<double> cot = mesh::edge_to_halfedge_weights(m, mesh::cotan_weights(m));
  const std::vector<double> mvc = mesh::mean_value_weights(m);
  int interior = 0;
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (m.vertex_is_boundary(v)) continue;
    ++interior;
    // Rounding only: weights and coordinates are O(1).
    CHECK(weighted_ring_sum(m, cot, v).norm() < 1e-13);
    CHECK(weighted_ring_sum(m, mvc, v).norm() < 1e-13);
  }
  CHECK(interior == 5 * 4);
}

TEST_CASE("mean-value weights: positive, not symmetric, known regular value") {
  SUBCASE("positive everywhere on a jittered grid and a torus") {
    for (const TriangleMesh& input : {t::flat_grid(5, 4, 0.3), t::torus(10, 7)}) {
      const HalfedgeMesh m = HalfedgeMesh::build(input);
      const std::vector<double> w = mesh::mean_value_weights(m);
      REQUIRE(static_cast<int>(w.size()) == m.num_halfedges());
      for (double x : w) CHECK(x > 0.0);
    }
  }
  SUBCASE("not symmetric in general") {
    const HalfedgeMesh m = HalfedgeMesh::build(t::flat_grid(5, 4, 0.3));
    const std::vector<double> w = mesh::mean_value_weights(m);
    double asymmetry = 0.0;
    for (int h = 0; h < m.num_halfedges(); ++h) {
      asymmetry = std::max(asymmetry, std::abs(w[h] - w[m.halfedge_twin(h)]));
    }
    CHECK(asymmetry > 1e-3);
  }
  SUBCASE("equilateral fan: 2 tan 30° / edge length") {
    // Regular hexagon of side 2 around vertex 0.
    std::vector<double> xyz = {0, 0, 0};
    std::vector<int> faces;
    for (int k = 0; k < 6; ++k) {
      const double a = k * 3.14159265358979323846 / 3;
      xyz.insert(xyz.end(), {2 * std::cos(a), 2 * std::sin(a), 0});
      faces.insert(faces.end(), {0, 1 + k, 1 + (k + 1) % 6});
    }
    const HalfedgeMesh m = HalfedgeMesh::build(t::make_mesh(xyz, faces));
    const std::vector<double> w = mesh::mean_value_weights(m);
    for (int h : m.vertex_outgoing(0)) CHECK(w[h] == doctest::Approx(1.0 / std::sqrt(3.0)).epsilon(1e-14));
  }
}

TEST_CASE("edge_to_halfedge_weights copies the edge weight to both halves") {
  const HalfedgeMesh m = HalfedgeMesh::build(t::tetrahedron());
  const std::vector<double> edge_w = {1, 2, 3, 4, 5, 6};
  const std::vector<double> w = mesh::edge_to_halfedge_weights(m, edge_w);
  for (int h = 0; h < m.num_halfedges(); ++h) CHECK(w[h] == edge_w[m.halfedge_edge(h)]);
}
