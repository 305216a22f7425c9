// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <utility>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/laplacian.h"
#include "tests/unit/common/test_meshes.h"

using volspline::mesh::HalfedgeMesh;
using volspline::mesh::LaplacianWeights;
using volspline::mesh::Triplet;
using volspline::mesh::TriangleMesh;
namespace mesh = volspline::mesh;
namespace t = volspline::test;

namespace {

std::vector<double> multiply(const std::vector<Triplet>& triplets, const std::vector<double>& u) {
  std::vector<double> out(u.size(), 0.0);
  for (const Triplet& e : triplets) out[e.row] += e.value * u[e.col];
  return out;
}

const LaplacianWeights kAll[] = {LaplacianWeights::Uniform, LaplacianWeights::Cotan,
                                 LaplacianWeights::MeanValue};

}  // namespace

TEST_CASE("uniform Laplacian of a tetrahedron") {
  const HalfedgeMesh m = HalfedgeMesh::build(t::tetrahedron());
  const std::vector<Triplet> l = mesh::laplacian_triplets(m, LaplacianWeights::Uniform);
  REQUIRE(l.size() == 16);
  for (size_t i = 0; i < l.size(); ++i) {
    if (i % 4 == 0) {  // each row starts with its diagonal
      CHECK(l[i].row == l[i].col);
      CHECK(l[i].value == -3.0);
    } else {
      CHECK(l[i].row != l[i].col);
      CHECK(l[i].value == 1.0);
    }
  }
}

TEST_CASE("every Laplacian kills constants (rows sum to zero)") {
  for (const TriangleMesh& input : {t::torus(9, 5), t::flat_grid(4, 4, 0.2), t::unit_cube()}) {
    const HalfedgeMesh m = HalfedgeMesh::build(input);
    for (LaplacianWeights kind : kAll) {
      const std::vector<double> lu = multiply(mesh::laplacian_triplets(m, kind),
                                           std::vector<double>(m.num_vertices(), 3.5));
      // Rounding of a sum of O(10) terms of size O(1).
      for (double x : lu) CHECK(std::abs(x) < 1e-12);
    }
  }
}

TEST_CASE("cotan and mean-value Laplacians are zero on linear functions at flat interior rows") {
  const HalfedgeMesh m = HalfedgeMesh::build(t::flat_grid(6, 6, 0.3));
  std::vector<double> u(m.num_vertices());
  for (int v = 0; v < m.num_vertices(); ++v) {
    u[v] = 2.0 * m.vertex_position(v).x() - 3.0 * m.vertex_position(v).y() + 1.0;
  }
  for (LaplacianWeights kind : {LaplacianWeights::Cotan, LaplacianWeights::MeanValue}) {
    const std::vector<double> lu = multiply(mesh::laplacian_triplets(m, kind), u);
    for (int v = 0; v < m.num_vertices(); ++v) {
      if (!m.vertex_is_boundary(v)) CHECK(std::abs(lu[v]) < 1e-12);  // rounding only
    }
  }
  // The uniform Laplacian has no linear precision on a jittered grid.
  const std::vector<double> lu = multiply(mesh::laplacian_triplets(m, LaplacianWeights::Uniform), u);
  double worst = 0.0;
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (!m.vertex_is_boundary(v)) worst = std::max(worst, std::abs(lu[v]));
  }
  CHECK(worst > 0.1);
}

TEST_CASE("cotan Laplacian is symmetric and negative semidefinite on a torus") {
  const HalfedgeMesh m = HalfedgeMesh::build(t::torus(10, 6));
  std::map<std::pair<int, int>, double> entries;
  for (const Triplet& e : mesh::laplacian_triplets(m, LaplacianWeights::Cotan)) {
    entries[{e.row, e.col}] += e.value;
  }
  for (const auto& [key, value] : entries) {
    CHECK(entries.at({key.second, key.first}) == doctest::Approx(value).epsilon(1e-14));
  }
  // u^T L u = -Σ_edges w_e (u_i - u_j)^2 ≤ 0 (all weights positive on this well-shaped torus).
  std::vector<double> u(m.num_vertices());
  for (int v = 0; v < m.num_vertices(); ++v) u[v] = std::sin(1.3 * v);
  double energy = 0.0;
  for (const auto& [key, value] : entries) energy += u[key.first] * value * u[key.second];
  CHECK(energy < 0.0);
}

TEST_CASE("unreferenced vertices get empty rows; custom weights are read per halfedge") {
  TriangleMesh mesh = t::tetrahedron();
  mesh.positions.conservativeResize(5, 3);
  mesh.positions.row(4) << 3, 3, 3;
  const HalfedgeMesh m = HalfedgeMesh::build(mesh);
  std::vector<double> w(m.num_halfedges());
  for (int h = 0; h < m.num_halfedges(); ++h) w[h] = h + 1.0;
  const std::vector<Triplet> l = mesh::laplacian_triplets(m, w);
  CHECK(l.size() == 16);
  for (const Triplet& e : l) {
    CHECK(e.row != 4);
    CHECK(e.col != 4);
  }
  for (const Triplet& e : l) {
    if (e.row == e.col) continue;
    bool found = false;
    for (int h : m.vertex_outgoing(e.row)) {
      if (m.halfedge_vertex(h) == e.col) found = e.value == w[h];
    }
    CHECK(found);
  }
}
