// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_report.h"
#include "core/polycube/gpc_builder.h"
#include "core/polycube/solid_decomposition.h"
#include "core/polycube/t_shape_layout.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

// A "T" of voxels (a bar of 7 cells, a stem of 4 under its middle, one cell thick) whose three
// ends become caps around one T-shape.
polycube::SolidDecomposition t_solid_decomposition() {
  mesh::TriangleMesh m = test::voxel_solid(7, 5, 1, 3, [](int x, int y, int) { return y == 4 || x == 3; });
  mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(m, "T");
  if (mesh::analyze_mesh(hm).signed_volume < 0) {
    m.triangles.col(1).swap(m.triangles.col(2));
    hm = mesh::HalfedgeMesh::build(m, "T");
  }
  polycube::DecompositionOptions d;
  d.morse.limb_persistence = 0.25;
  return polycube::decompose_solid(hm, 0, d);
}

// The T-shape's centre: glued to its two arms (faces x = 0, x = 1) and its stem (face z = 0).
const polycube::GpcCuboid& centre_of(const polycube::GpcConstruction& c) {
  for (const polycube::GpcCuboid& q : c.domain.cuboids)
    if (q.face_interface[0] >= 0 && q.face_interface[1] >= 0 && q.face_interface[4] >= 0) return q;
  FAIL("no centre cuboid");
  return c.domain.cuboids.front();
}

}  // namespace

TEST_CASE("T-shape layout: at the crotch's height the centre is thinner than the bar; lower, it spans it") {
  const polycube::SolidDecomposition decomposition = t_solid_decomposition();
  polycube::SolidDecomposition a = decomposition, b = decomposition;
  const polycube::GpcConstruction at_crotch = polycube::build_gpc(a, 1.0);
  polycube::TShapeLayoutOptions lower;
  lower.concave_corner_height = 0.6;
  const polycube::GpcConstruction taller = polycube::build_gpc(b, 1.0, {}, true, lower);
  REQUIRE(at_crotch.domain.t_shapes == 1);
  REQUIRE(taller.domain.t_shapes == 1);
  CHECK(taller.domain.cuboids.size() == at_crotch.domain.cuboids.size());
  // The bar is y in [4, 5] (voxel units), the stem x in [3, 4] below it: the centre's height is
  // its extent along the stem, from its bottom face (corners 0..3, on the concave edges at the
  // bar's underside y = 4 and the stem's sides) to its top face (corners 4..7, on the bar's top).
  auto mean_height = [](const polycube::GpcCuboid& q) {
    double h = 0.0;
    for (int k = 0; k < 4; ++k) h += std::abs(q.corner_xyz[k + 4].y() - q.corner_xyz[k].y());
    return h / 4.0;
  };
  auto mean_bottom = [](const polycube::GpcCuboid& q) {
    double y = 0.0;
    for (int k = 0; k < 4; ++k) y += q.corner_xyz[k].y();
    return y / 4.0;
  };
  const polycube::GpcCuboid &c0 = centre_of(at_crotch), &c1 = centre_of(taller);
  MESSAGE("centre height " << mean_height(c0) << " -> " << mean_height(c1) << ", bottom y " << mean_bottom(c0) << " -> "
                           << mean_bottom(c1));
  // The crotch (the bar's top above the stem) is as far from the stem loop as points of the
  // bar's underside beside the junction: the concave corners sit there, above the concave edges,
  // and the centre is flatter than the bar it joins.
  CHECK(mean_bottom(c0) > 4.0);
  CHECK(mean_height(c0) < 1.0);
  // Lower, they reach the concave edges: the centre spans the bar's thickness.
  CHECK(mean_bottom(c1) <= 4.0);
  CHECK(mean_height(c1) >= 1.0);
}
