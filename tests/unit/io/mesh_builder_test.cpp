// SPDX-License-Identifier: MIT
#include "core/io/mesh_builder.h"

#include <doctest/doctest.h>

#include "tests/unit/io/io_test_util.h"

using namespace volspline::io;
using volspline::io::test::error_of;
using volspline::io::test::has;

TEST_CASE("builder: fan triangulation and finish") {
  MeshBuilder builder;
  for (int k = 0; k < 5; ++k) builder.add_vertex(k, 2 * k, 3 * k);
  const int pentagon[] = {4, 3, 2, 1, 0};
  builder.add_polygon(pentagon, 5);
  CHECK(builder.num_triangles() == 3);
  const auto m = builder.finish("p");
  CHECK(m.num_vertices() == 5);
  CHECK(m.triangles.row(2) == Eigen::RowVector3i(4, 1, 0));
  CHECK(m.positions.row(3) == Eigen::RowVector3d(3, 6, 9));
}

TEST_CASE("builder: empty and face-less meshes are errors naming the file") {
  MeshBuilder empty;
  CHECK(has(error_of([&] { empty.finish("e.obj"); }), "e.obj: no vertices"));
  MeshBuilder points;
  points.add_vertex(0, 0, 0);
  CHECK(has(error_of([&] { points.finish("p.obj"); }), "p.obj: no faces"));
}
