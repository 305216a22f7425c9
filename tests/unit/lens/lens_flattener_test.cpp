// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/lens/flatten.h"
#include "core/lens/lens_flattener.h"
#include "core/lens/lens_mesh.h"
#include "tests/unit/common/test_lenses.h"

using namespace volspline;
using namespace volspline::lens;

namespace {
LensMesh lens_bump(double h0, int grid = 20) {
  return volspline::test::circle_lens_mesh("circle:40,36,14", 80, 70, h0, grid);
}
FlattenOptions with_alpha(double alpha) {
  FlattenOptions o;
  o.alpha = alpha;
  o.height_unit = 1.0;
  return o;
}
// Bit-for-bit: the session must reproduce flatten_lens exactly, not approximately.
bool identical(const FlattenResult& a, const FlattenResult& b) {
  return a.positions.rows() == b.positions.rows() && (a.positions.array() == b.positions.array()).all() &&
         a.iterations == b.iterations && a.converged == b.converged && a.energy == b.energy;
}
}  // namespace

TEST_CASE("one factorization, many alphas: every flatten equals a fresh flatten_lens bit for bit") {
  const LensMesh m = lens_bump(1.0);
  LensFlattener flattener;
  CHECK_FALSE(flattener.ready());
  flattener.compute(m.xyz, m.triangles, m.pinned, 1.0);
  REQUIRE(flattener.ready());
  CHECK(flattener.vertices() == m.xyz.rows());
  const Eigen::MatrixX2d start = m.xyz.leftCols<2>();
  // Out of order and repeated: no state leaks from one flatten into the next.
  for (double alpha : {1.0, 0.0, 0.35, 1.0, 0.0}) {
    const FlattenResult reused = flattener.flatten(start, with_alpha(alpha));
    const FlattenResult fresh = flatten_lens(m.xyz, m.triangles, m.pinned, start, with_alpha(alpha));
    CHECK(identical(reused, fresh));
    CHECK(reused.iterations > 0);
    CHECK(reused.ms_factorize == flattener.ms_factorize());
  }
}

TEST_CASE("a new start moves the pinned vertices and is matched by flatten_lens") {
  const LensMesh m = lens_bump(0.8);
  LensFlattener flattener;
  flattener.compute(m.xyz, m.triangles, m.pinned, 1.0);
  Eigen::MatrixX2d start = m.xyz.leftCols<2>();
  start.col(0).array() += 3.0;  // a translated frame: the pinned rhs must follow the start
  const FlattenResult reused = flattener.flatten(start, with_alpha(0.5));
  CHECK(identical(reused, flatten_lens(m.xyz, m.triangles, m.pinned, start, with_alpha(0.5))));
  for (int v = 0; v < m.xyz.rows(); ++v)
    if (m.pinned[v]) CHECK(reused.positions.row(v) == start.row(v));
}

TEST_CASE("max_iterations and tol_rel are per flatten") {
  const LensMesh m = lens_bump(1.2);
  LensFlattener flattener;
  flattener.compute(m.xyz, m.triangles, m.pinned, 1.0);
  FlattenOptions one = with_alpha(0.0);
  one.max_iterations = 1;
  const FlattenResult r1 = flattener.flatten(m.xyz.leftCols<2>(), one);
  CHECK(r1.iterations == 1);
  CHECK_FALSE(r1.converged);
  const FlattenResult r = flattener.flatten(m.xyz.leftCols<2>(), with_alpha(0.0));
  CHECK(r.converged);
  CHECK(r.energy <= r1.energy);  // the local/global iterations never increase Eq. 6.2
}

TEST_CASE("all pinned: flatten returns the start untouched") {
  LensMesh m = lens_bump(1.0, 8);
  std::fill(m.pinned.begin(), m.pinned.end(), char(1));
  LensFlattener flattener;
  flattener.compute(m.xyz, m.triangles, m.pinned, 1.0);
  const FlattenResult r = flattener.flatten(m.xyz.leftCols<2>(), with_alpha(0.0));
  CHECK(r.iterations == 0);
  CHECK((r.positions.array() == m.xyz.leftCols<2>().array()).all());
}

TEST_CASE("flattener errors name the problem") {
  const LensMesh m = lens_bump(1.0, 8);
  LensFlattener flattener;
  CHECK_THROWS_WITH_AS(flattener.flatten(m.xyz.leftCols<2>(), with_alpha(0.0)),
                       doctest::Contains("before a successful compute"), Error);
  flattener.compute(m.xyz, m.triangles, m.pinned, 1.0);
  const Eigen::MatrixX2d short_start = m.xyz.topRows(3).leftCols<2>();
  CHECK_THROWS_WITH_AS(flattener.flatten(short_start, with_alpha(0.0)), doctest::Contains("start has 3 rows"), Error);
  // A free vertex in no triangle gives W an exactly zero row: singular; the session is left empty.
  mesh::Positions xyz(m.xyz.rows() + 1, 3);
  xyz << m.xyz, Eigen::RowVector3d(1, 1, 0);
  std::vector<char> pinned = m.pinned;
  pinned.push_back(0);
  CHECK_THROWS_WITH_AS(flattener.compute(xyz, m.triangles, pinned, 1.0), doctest::Contains("singular"), Error);
  CHECK_FALSE(flattener.ready());
}
