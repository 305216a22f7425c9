// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/io/mesh_io.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_report.h"
#include "tests/unit/common/test_meshes.h"

using volspline::mesh::analyze_mesh;
using volspline::mesh::HalfedgeMesh;
using volspline::mesh::MeshReport;
using volspline::mesh::TriangleMesh;
namespace t = volspline::test;

namespace {

MeshReport report_of(const TriangleMesh& mesh) { return analyze_mesh(HalfedgeMesh::build(mesh)); }

}  // namespace

TEST_CASE("tetrahedron and cube: closed genus-0 spheres") {
  for (const TriangleMesh& mesh : {t::tetrahedron(), t::unit_cube()}) {
    const MeshReport r = report_of(mesh);
    CHECK(r.closed);
    CHECK(r.manifold);
    CHECK(r.consistently_oriented);
    CHECK(r.num_boundary_loops == 0);
    CHECK(r.num_components == 1);
    CHECK(r.euler_characteristic == 2);
    CHECK(r.genus == 0);
    CHECK(r.num_degenerate_faces == 0);
    CHECK(r.first_degenerate_face == -1);
    CHECK(r.signed_volume > 0.0);
  }
  const MeshReport cube = report_of(t::unit_cube());
  CHECK(cube.num_vertices == 8);
  CHECK(cube.num_edges == 18);
  CHECK(cube.num_faces == 12);
  CHECK(cube.bbox_min == Eigen::Vector3d(0, 0, 0));
  CHECK(cube.bbox_max == Eigen::Vector3d(1, 1, 1));
  // Exact in binary: every product is a small integer.
  CHECK(cube.signed_volume == 1.0);
  CHECK(report_of(t::tetrahedron()).signed_volume == doctest::Approx(1.0 / 6.0).epsilon(1e-14));
}

TEST_CASE("open square: one boundary loop, genus 0, a disk") {
  const MeshReport r = report_of(t::flat_grid(4, 3));
  CHECK(!r.closed);
  CHECK(r.num_boundary_edges == 14);
  CHECK(r.num_boundary_loops == 1);
  CHECK(r.num_components == 1);
  CHECK(r.euler_characteristic == 1);
  CHECK(r.genus == 0);
}

TEST_CASE("annulus: two boundary loops, genus 0") {
  // A torus grid with one ring of quads removed is a cylinder.
  TriangleMesh mesh = t::torus(8, 6);
  mesh.triangles.conservativeResize(mesh.num_faces() - 2 * 6, 3);
  const MeshReport r = report_of(mesh);
  CHECK(r.num_boundary_loops == 2);
  CHECK(r.euler_characteristic == 0);
  CHECK(r.genus == 0);
}

TEST_CASE("torus: genus 1, outward") {
  const MeshReport r = report_of(t::torus(12, 7));
  CHECK(r.closed);
  CHECK(r.euler_characteristic == 0);
  CHECK(r.genus == 1);
  CHECK(r.signed_volume > 0.0);
}

TEST_CASE("two disjoint tetrahedra: 2 components, genus undefined") {
  const MeshReport r = report_of(t::two_tetrahedra());
  CHECK(r.num_components == 2);
  CHECK(r.euler_characteristic == 4);
  CHECK(r.genus == -1);
  CHECK(r.closed);
}

TEST_CASE("flipped face, degenerate face and unreferenced vertex are reported") {
  TriangleMesh mesh = t::unit_cube();
  std::swap(mesh.triangles(5, 1), mesh.triangles(5, 2));
  mesh.positions.conservativeResize(9, 3);
  mesh.positions.row(8) << 0.5, 0.5, 0.5;
  MeshReport r = report_of(mesh);
  CHECK(!r.consistently_oriented);
  CHECK(r.num_flipped_faces == 1);
  CHECK(r.num_unreferenced_vertices == 1);
  CHECK(r.num_vertices == 9);
  CHECK(r.euler_characteristic == 2);  // the stray vertex is not part of the surface
  CHECK(r.genus == 0);

  // The apex moved onto edge (0, 1) makes face (0, 1, 3) a zero-area sliver; the others
  // become flat but keep their area.
  TriangleMesh squashed = t::tetrahedron();
  squashed.positions.row(3) << 0.5, 0.0, 0.0;
  r = report_of(squashed);
  CHECK(r.num_degenerate_faces == 1);
  CHECK(r.first_degenerate_face == 1);
}

TEST_CASE("genus of every shared test mesh matches SOURCES.md") {
  const std::string dir = std::string(VOLSPLINE_SHARED_DATA) + "/meshes/";
  std::ifstream table(dir + "SOURCES.md");
  REQUIRE(table.good());
  std::string line;
  int checked = 0;
  while (std::getline(table, line)) {
    // Table rows: | file | V | F | closed | genus | size | repo |
    if (line.rfind("| ", 0) != 0 || line.find(".o") == std::string::npos) continue;
    std::vector<std::string> cells;
    std::stringstream row(line.substr(1));
    std::string cell;
    while (std::getline(row, cell, '|')) {
      const size_t a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
      cells.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
    }
    REQUIRE(cells.size() >= 5);
    CAPTURE(cells[0]);
    const MeshReport r = report_of(volspline::io::read_mesh(dir + cells[0]));
    CHECK(r.num_vertices == std::stoi(cells[1]));
    CHECK(r.num_faces == std::stoi(cells[2]));
    CHECK(r.closed == (cells[3] == "yes"));
    CHECK(r.genus == std::stoi(cells[4]));
    CHECK(r.num_components == 1);
    CHECK(r.consistently_oriented);
    CHECK(r.signed_volume > 0.0);
    ++checked;
  }
  CHECK(checked == 13);
}
