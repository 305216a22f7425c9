// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/lens/flatten.h"
#include "core/lens/lens_measures.h"
#include "core/lens/lens_mesh.h"
#include "tests/unit/common/test_lenses.h"

using namespace volspline::lens;

namespace {
LensMesh bump(double h0, int grid = 24) {
  return volspline::test::circle_lens_mesh("circle:50,50,20", 100, 100, h0, grid);
}
FlattenResult flatten(const LensMesh& m, double alpha) {
  FlattenOptions o;
  o.alpha = alpha;
  o.height_unit = 100;
  return flatten_lens(m.xyz, m.triangles, m.pinned, m.xyz.leftCols<2>(), o);
}
}  // namespace

TEST_CASE("a flat mesh is already flat: zero energy, positions unchanged") {
  const LensMesh m = bump(0.0);
  const FlattenResult r = flatten(m, 0.0);
  CHECK(r.converged);
  CHECK(r.energy == doctest::Approx(0.0).epsilon(1e-12));
  CHECK((r.positions - m.xyz.leftCols<2>()).cwiseAbs().maxCoeff() < 1e-9);  // direct solve, round-off only
}

TEST_CASE("flattening keeps pinned vertices and never folds for the thesis' alpha values") {
  const LensMesh m = bump(1.0);
  for (double alpha : {0.0, 0.001, 0.01, 1.0}) {
    const FlattenResult r = flatten(m, alpha);
    CHECK(r.converged);
    const ShapeDistortion d = measure_distortion(r.positions, m.xyz.leftCols<2>(), m.triangles);
    CHECK(d.flipped_triangles == 0);
    for (int v = 0; v < m.xyz.rows(); ++v)
      if (m.pinned[v]) CHECK(r.positions.row(v) == m.xyz.row(v).head<2>());
  }
}

TEST_CASE("rigid metric keeps edge lengths better, conformal metric keeps angles better") {
  const LensMesh m = bump(1.0);
  const FlattenResult rigid = flatten(m, 0.0), conformal = flatten(m, 1.0);
  CHECK(edge_length_error(m.xyz, rigid.positions, m.triangles) < edge_length_error(m.xyz, conformal.positions, m.triangles));
  CHECK(angle_error(m.xyz, conformal.positions, m.triangles) < angle_error(m.xyz, rigid.positions, m.triangles));
}
