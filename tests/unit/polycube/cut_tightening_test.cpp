// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <vector>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_report.h"
#include "core/pipeline/gpc_job.h"
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

// The shortest cuts keep the level-set decomposition's pieces, are no longer, bound discs inside
// the solid, and leave every face in one piece of a closed surface of the same genus.
void check_same_topology(const polycube::SolidDecomposition& a, const polycube::SolidDecomposition& b, int genus) {
  REQUIRE(a.pieces.size() == b.pieces.size());
  REQUIRE(a.loops.size() == b.loops.size());
  for (std::size_t p = 0; p < a.pieces.size(); ++p) CHECK(a.pieces[p].kind == b.pieces[p].kind);
  CHECK(total_cut_length(b) <= total_cut_length(a) + 1e-12);
  for (const polycube::CutLoop& l : b.loops) {
    const polycube::DiscEmbedding e = polycube::check_loop_disc(b.mesh, l.vertices);
    CHECK(e.num_outside == 0);
    CHECK(e.num_intersections == 0);
  }
  std::vector<int> count(b.mesh.num_faces(), 0);
  for (const polycube::SolidPiece& p : b.pieces)
    for (int f : p.faces) ++count[f];
  CHECK(std::count(count.begin(), count.end(), 1) == b.mesh.num_faces());
  const mesh::MeshReport r = mesh::analyze_mesh(mesh::HalfedgeMesh::build(b.mesh, "tightened"));
  CHECK(r.closed);
  CHECK(r.genus == genus);
}

}  // namespace

TEST_CASE("cut tightening: a wavy cut between two tubes of a torus becomes a straight meridian") {
  const int nu = 32, nv = 16;
  const double r = 0.35, pi = 3.14159265358979323846;
  polycube::SolidDecomposition d;
  d.mesh = test::torus(nu, nv, 1.0, r);
  d.genus = 1;
  d.value.assign(d.mesh.num_vertices(), 0.0);
  d.parent_face.resize(d.mesh.num_faces());
  std::iota(d.parent_face.begin(), d.parent_face.end(), 0);
  // Vertex (i, j) = i·nv + j. Cut 0 goes around the tube once with four diagonal steps, straight
  // on, then back along the ring j = 0 (isotopic to a meridian); cut 1 is the meridian i = 16.
  std::vector<int> wavy, straight;
  for (int j = 0; j < nv; ++j) wavy.push_back(std::min(j, 4) * nv + j);
  for (int i = 4; i >= 1; --i) wavy.push_back(i * nv);
  for (int j = 0; j < nv; ++j) straight.push_back(16 * nv + j);
  // The two tubes: faces connected without crossing a cut edge.
  const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(d.mesh, "torus");
  std::set<std::pair<int, int>> cut_edges;
  for (const auto* loop : {&wavy, &straight})
    for (std::size_t k = 0; k < loop->size(); ++k) {
      const int a = (*loop)[k], b = (*loop)[(k + 1) % loop->size()];
      cut_edges.insert({std::min(a, b), std::max(a, b)});
    }
  std::vector<int> tube(hm.num_faces(), -1);
  for (int seed = 0, count = 0; seed < hm.num_faces(); ++seed) {
    if (tube[seed] >= 0) continue;
    std::vector<int> stack{seed};
    tube[seed] = count;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      for (int h : hm.face_halfedges(f)) {
        const int a = hm.halfedge_source(h), b = hm.halfedge_vertex(h);
        const int g = hm.halfedge_face(hm.halfedge_twin(h));
        if (cut_edges.count({std::min(a, b), std::max(a, b)}) || tube[g] >= 0) continue;
        tube[g] = count;
        stack.push_back(g);
      }
    }
    ++count;
  }
  REQUIRE(*std::max_element(tube.begin(), tube.end()) == 1);
  d.pieces.resize(2);
  for (int f = 0; f < hm.num_faces(); ++f) d.pieces[tube[f]].faces.push_back(f);
  for (const auto* loop : {&wavy, &straight}) {
    polycube::CutLoop c;
    c.vertices = *loop;
    for (int h : hm.vertex_outgoing((*loop)[0]))
      if (hm.halfedge_vertex(h) == (*loop)[1]) c.piece = {tube[hm.halfedge_face(h)], tube[hm.halfedge_face(hm.halfedge_twin(h))]};
    const int id = static_cast<int>(d.loops.size());
    d.pieces[c.piece[0]].boundary.push_back({id, 0});
    d.pieces[c.piece[1]].boundary.push_back({id, 1});
    d.loops.push_back(c);
  }
  for (polycube::SolidPiece& p : d.pieces) p.kind = polycube::PieceKind::Tube;

  const double meridian = nv * 2.0 * r * std::sin(pi / nv);
  REQUIRE(loop_length(d.mesh, wavy) > 1.3 * meridian);
  const polycube::CutTightening t = polycube::tighten_cut_loops(d);
  CHECK(t.num_tightened == 1);
  CHECK(t.length_after == doctest::Approx(2.0 * meridian).epsilon(1e-12));
  // One ring i = const near the wavy cut, every j once; the straight cut is where it was.
  const std::vector<int>& loop = d.loops[0].vertices;
  REQUIRE(static_cast<int>(loop.size()) == nv);
  std::set<int> rings, js;
  for (int v : loop) {
    rings.insert(v / nv);
    js.insert(v % nv);
  }
  CHECK(rings.size() == 1);
  CHECK(static_cast<int>(js.size()) == nv);
  CHECK(d.loops[1].vertices == straight);
  // Its disc is a meridian disc: inside, no crossing. No chord to split; every face in one tube,
  // each tube an annulus.
  const polycube::DiscEmbedding e = polycube::check_loop_disc(d.mesh, loop);
  CHECK(e.num_outside == 0);
  CHECK(e.num_intersections == 0);
  CHECK(d.mesh.num_faces() == 2 * nu * nv);
  CHECK(d.pieces[0].faces.size() + d.pieces[1].faces.size() == static_cast<std::size_t>(2 * nu * nv));
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
  check_same_topology(a, b, 2);
}

TEST_CASE("cut tightening: a sheared three-hole slab keeps its topology with shorter, embedded cuts") {
  mesh::TriangleMesh slab = test::voxel_solid(11, 3, 2, 2, [](int x, int y, int) { return !(y == 1 && x % 4 == 1); });
  for (int v = 0; v < slab.num_vertices(); ++v) slab.positions(v, 0) += 1.5 * slab.positions(v, 1) + 0.7 * slab.positions(v, 2);
  const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(slab, "slab");
  REQUIRE(mesh::analyze_mesh(hm).genus == 3);
  polycube::DecompositionOptions level_set;
  level_set.cuts = polycube::CutPlacement::LevelSet;
  const polycube::SolidDecomposition a = polycube::decompose_solid(hm, 3, level_set);
  const polycube::SolidDecomposition b = polycube::decompose_solid(hm, 3);
  // The shear tilts the bars against the Morse function's level sets: some cuts straighten.
  CHECK(b.num_tightened_cuts >= 1);
  CHECK(total_cut_length(b) < 0.99 * total_cut_length(a));
  check_same_topology(a, b, 3);
  // The whole construction runs on the moved cuts: every disc embedded, bijective surface maps
  // (measured before the volumetric grid, so its untangling is left out).
  pipeline::GpcOptions o;
  o.grid.target_nodes = 2000;
  o.grid.untangle = param::GpcGridOptions::Untangle::Off;
  const pipeline::GpcResult g = pipeline::run_gpc(slab, "slab", o);
  CHECK(g.stats.tightened_cuts == b.num_tightened_cuts);
  CHECK(g.stats.cut_disc_intersections == 0);
  CHECK(g.stats.flipped_triangles == 0);
  CHECK(g.stats.t_shapes == 4);
}
