// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <vector>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_report.h"
#include "core/polycube/cut_tightening.h"
#include "core/polycube/interface_disc.h"
#include "core/polycube/solid_decomposition.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

double loop_length(const mesh::TriangleMesh& m, const std::vector<int>& loop) {
  double s = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i)
    s += (m.positions.row(loop[i]) - m.positions.row(loop[(i + 1) % loop.size()])).norm();
  return s;
}

double total_cut_length(const polycube::SolidDecomposition& d) {
  double s = 0.0;
  for (const polycube::CutLoop& l : d.loops) s += loop_length(d.mesh, l.vertices);
  return s;
}

}  // namespace

TEST_CASE("cut tightening: a wavy cut around a torus's tube becomes a straight meridian") {
  const int nu = 32, nv = 16;
  const double r = 0.35, pi = 3.14159265358979323846;
  polycube::SolidDecomposition d;
  d.mesh = test::torus(nu, nv, 1.0, r);
  d.genus = 1;
  d.value.assign(d.mesh.num_vertices(), 0.0);
  d.parent_face.resize(d.mesh.num_faces());
  std::iota(d.parent_face.begin(), d.parent_face.end(), 0);
  // Vertex (i, j) = i·nv + j. Around the tube once: four diagonal steps, straight on, then back
  // along the ring j = 0; isotopic to a meridian, one tube closed on itself.
  polycube::CutLoop wavy;
  for (int j = 0; j < nv; ++j) wavy.vertices.push_back(std::min(j, 4) * nv + j);
  for (int i = 4; i >= 1; --i) wavy.vertices.push_back(i * nv);
  wavy.piece = {0, 0};
  d.loops.push_back(wavy);
  polycube::SolidPiece tube;
  tube.faces.resize(d.mesh.num_faces());
  std::iota(tube.faces.begin(), tube.faces.end(), 0);
  tube.boundary = {{0, 0}, {0, 1}};
  tube.kind = polycube::PieceKind::Tube;
  d.pieces.push_back(tube);

  const double meridian = nv * 2.0 * r * std::sin(pi / nv);
  REQUIRE(loop_length(d.mesh, wavy.vertices) > 1.3 * meridian);
  const polycube::CutTightening t = polycube::tighten_cut_loops(d);
  CHECK(t.num_tightened == 1);
  CHECK(t.length_after == doctest::Approx(meridian).epsilon(1e-12));
  // One ring i = const, every j once, consecutive j along the loop.
  const std::vector<int>& loop = d.loops[0].vertices;
  REQUIRE(static_cast<int>(loop.size()) == nv);
  std::set<int> rings, js;
  for (int v : loop) {
    rings.insert(v / nv);
    js.insert(v % nv);
  }
  CHECK(rings.size() == 1);
  CHECK(static_cast<int>(js.size()) == nv);
  // Its disc is a meridian disc: inside, no crossing. The mesh had no chord to split.
  const polycube::DiscEmbedding e = polycube::check_loop_disc(d.mesh, loop);
  CHECK(e.num_outside == 0);
  CHECK(e.num_intersections == 0);
  CHECK(d.mesh.num_faces() == 2 * nu * nv);
}

TEST_CASE("cut tightening: a two-hole solid keeps its pieces and loops, with shorter or equal cuts") {
  mesh::TriangleMesh slab = test::two_hole_slab(3);
  mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(slab, "slab");
  if (mesh::analyze_mesh(hm).signed_volume < 0) {
    slab.triangles.col(1).swap(slab.triangles.col(2));
    hm = mesh::HalfedgeMesh::build(slab, "slab");
  }
  polycube::DecompositionOptions level_set;
  level_set.cuts = polycube::CutPlacement::LevelSet;
  const polycube::SolidDecomposition a = polycube::decompose_solid(hm, 2, level_set);
  const polycube::SolidDecomposition b = polycube::decompose_solid(hm, 2);
  REQUIRE(a.pieces.size() == b.pieces.size());
  REQUIRE(a.loops.size() == b.loops.size());
  for (std::size_t p = 0; p < a.pieces.size(); ++p) CHECK(a.pieces[p].kind == b.pieces[p].kind);
  CHECK(total_cut_length(b) <= total_cut_length(a) + 1e-12);
  for (const polycube::CutLoop& l : b.loops) {
    const polycube::DiscEmbedding e = polycube::check_loop_disc(b.mesh, l.vertices);
    CHECK(e.num_outside == 0);
    CHECK(e.num_intersections == 0);
  }
  // Every face in one piece, and the surface is still the closed genus-2 surface.
  std::vector<int> count(b.mesh.num_faces(), 0);
  for (const polycube::SolidPiece& p : b.pieces)
    for (int f : p.faces) ++count[f];
  CHECK(std::count(count.begin(), count.end(), 1) == b.mesh.num_faces());
  const mesh::MeshReport r = mesh::analyze_mesh(mesh::HalfedgeMesh::build(b.mesh, "tightened"));
  CHECK(r.closed);
  CHECK(r.genus == 2);
}
