// SPDX-License-Identifier: MIT
#include "core/param/volumetric_grid_map.h"

#include <doctest/doctest.h>

#include "core/common/error.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

TEST_CASE("the volumetric grid of a cube is the affine lattice") {
  const auto m = mesh::HalfedgeMesh::build(test::subdivided_cube(4), "cube");
  const auto map = param::compute_cuboid_surface_map(m, polycube::compute_cuboid_layout(m));
  const param::CuboidSurfaceLocator locator(m, map);
  param::VolumetricGridOptions options;
  options.nodes = {5, 7, 6};
  const auto grid = param::compute_volumetric_grid_map(locator, options);
  CHECK(grid.converged);
  CHECK(grid.num_hexes == 4 * 6 * 5);
  CHECK(grid.num_inverted_hexes == 0);
  // Linear functions are discrete harmonic on a uniform lattice (Eq. 3.1), so the nodes are an
  // affine image of the parameters; tolerance from the CG residual.
  const Eigen::Vector3d o = grid.xyz.row(0).transpose();
  const Eigen::Vector3d du = grid.xyz.row(param::grid_node_index(grid.nodes, 4, 0, 0)).transpose() - o;
  const Eigen::Vector3d dv = grid.xyz.row(param::grid_node_index(grid.nodes, 0, 6, 0)).transpose() - o;
  const Eigen::Vector3d dw = grid.xyz.row(param::grid_node_index(grid.nodes, 0, 0, 5)).transpose() - o;
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 5; ++i) {
        const Eigen::Vector3d expected = o + du * i / 4.0 + dv * j / 6.0 + dw * k / 5.0;
        CHECK((grid.xyz.row(param::grid_node_index(grid.nodes, i, j, k)).transpose() - expected).norm() < 1e-7);
      }
  CHECK(grid.min_scaled_jacobian == doctest::Approx(1.0).epsilon(1e-6));
}

TEST_CASE("grid node counts are checked") {
  const auto m = mesh::HalfedgeMesh::build(test::subdivided_cube(2), "cube");
  const auto map = param::compute_cuboid_surface_map(m, polycube::compute_cuboid_layout(m));
  const param::CuboidSurfaceLocator locator(m, map);
  param::VolumetricGridOptions options;
  options.nodes = {1, 5, 5};
  CHECK_THROWS_WITH_AS(param::compute_volumetric_grid_map(locator, options),
                       doctest::Contains("1 nodes along axis 0"), Error);
}
