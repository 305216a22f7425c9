// SPDX-License-Identifier: MIT
#include "core/param/cuboid_surface_map.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/io/mesh_io.h"
#include "core/param/cuboid_surface_locator.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

// A cube sphere stretched 4× above z = 0.5: a map that needs area balancing.
mesh::TriangleMesh bumpy_cube_sphere(int n) {
  mesh::TriangleMesh bumpy = test::cube_sphere(n);
  for (int v = 0; v < bumpy.num_vertices(); ++v)
    if (bumpy.positions(v, 2) > 0.5) bumpy.positions(v, 2) = 0.5 + 4.0 * (bumpy.positions(v, 2) - 0.5);
  return bumpy;
}

}  // namespace

TEST_CASE("cube face coordinates round-trip") {
  for (int f = 0; f < 6; ++f) {
    const Eigen::Vector3d p = polycube::cube_face_point(f, 0.25, 0.75);
    CHECK(p(f / 2) == f % 2);
    const Eigen::Vector2d st = polycube::cube_face_coordinates(f, p);
    CHECK(st.x() == 0.25);
    CHECK(st.y() == 0.75);
  }
}

TEST_CASE("the surface map of a subdivided cube is the identity up to scale") {
  const auto m = mesh::HalfedgeMesh::build(test::subdivided_cube(4), "cube");
  const auto layout = polycube::compute_cuboid_layout(m);
  for (auto weights : {param::SurfaceWeights::MeanValue, param::SurfaceWeights::Cotan}) {
    param::CuboidSurfaceMapOptions options;
    options.weights = weights;
    const auto map = param::compute_cuboid_surface_map(m, layout, options);
    CHECK(map.num_flipped == 0);
    // The layout's labelling may differ from the xyz axes by a cube symmetry, so compare
    // distances: the map is an isometry up to the factor 1/2 (uniform grid, harmonic weights
    // reproduce linear functions; tolerance from the CG residual).
    for (int i = 0; i < m.num_vertices(); ++i) {
      for (int j = 0; j < m.num_vertices(); j += 7) {
        const double dx = (m.vertex_position(i) - m.vertex_position(j)).norm();
        const double du = (map.uvw.row(i) - map.uvw.row(j)).norm();
        CHECK(du == doctest::Approx(dx / 2).epsilon(1e-7));
      }
    }
    const param::CuboidSurfaceLocator locator(m, map);
    for (int i = 0; i < m.num_vertices(); ++i) {
      const Eigen::Vector3d x = locator.locate_uvw(map.uvw.row(i).transpose());
      CHECK((x - m.vertex_position(i)).norm() < 1e-7);
    }
  }
}

TEST_CASE("the surface map of a sphere is bijective and on the cube surface") {
  const auto m = mesh::HalfedgeMesh::build(test::cube_sphere(8), "sphere");
  const auto layout = polycube::compute_cuboid_layout(m);
  const auto map = param::compute_cuboid_surface_map(m, layout);
  CHECK(map.num_flipped == 0);
  for (int i = 0; i < m.num_vertices(); ++i) {
    const Eigen::Vector3d p = map.uvw.row(i).transpose();
    CHECK(p.minCoeff() >= 0.0);
    CHECK(p.maxCoeff() <= 1.0);
    CHECK(std::min(p.minCoeff(), 1.0 - p.maxCoeff()) == 0.0);
  }
  // Inverse lookup of a face centroid parameter gives a point on the sphere (within the chord
  // error of the 8×8 faces).
  const param::CuboidSurfaceLocator locator(m, map);
  for (int f = 0; f < 6; ++f) {
    const double r = locator.locate(f, 0.37, 0.61).norm();
    CHECK(r > 0.97);
    CHECK(r <= 1.0 + 1e-12);
  }
}

namespace {

// Surface-area-weighted mean of |log(parameter area share / surface area share)| over the
// triangles, shares taken within each cube face (the faces are mapped independently): 0 for an
// area-preserving map.
double area_distortion(const mesh::HalfedgeMesh& m, const param::CuboidSurfaceMap& map) {
  std::vector<double> surface(m.num_faces()), parameter(m.num_faces());
  double surface_face[6] = {}, parameter_face[6] = {}, surface_total = 0.0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const auto c = m.face_vertices(f);
    surface[f] = (m.vertex_position(c[1]) - m.vertex_position(c[0])).cross(m.vertex_position(c[2]) - m.vertex_position(c[0])).norm();
    const Eigen::Vector3d u0 = map.uvw.row(c[0]).transpose();
    parameter[f] = (Eigen::Vector3d(map.uvw.row(c[1]).transpose()) - u0).cross(Eigen::Vector3d(map.uvw.row(c[2]).transpose()) - u0).norm();
    surface_face[map.face_region[f]] += surface[f];
    parameter_face[map.face_region[f]] += parameter[f];
    surface_total += surface[f];
  }
  double sum = 0.0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const int r = map.face_region[f];
    sum += surface[f] / surface_total *
           std::abs(std::log((parameter[f] / parameter_face[r]) / (surface[f] / surface_face[r])));
  }
  return sum;
}

}  // namespace

TEST_CASE("area balancing keeps the map bijective and gives a protrusion more parameter area") {
  const mesh::TriangleMesh bumpy = bumpy_cube_sphere(10);
  const auto m = mesh::HalfedgeMesh::build(bumpy, "bumpy");
  const auto layout = polycube::compute_cuboid_layout(m);
  const auto plain = param::compute_cuboid_surface_map(m, layout);
  param::CuboidSurfaceMapOptions options;
  options.area_balance_iterations = 4;
  const auto balanced = param::compute_cuboid_surface_map(m, layout, options);
  CHECK(balanced.num_flipped == 0);
  // Poly-edges are fixed by arc length in both maps.
  for (const auto& path : layout.poly_edges)
    for (int v : path) CHECK(balanced.uvw.row(v) == plain.uvw.row(v));
  CAPTURE(area_distortion(m, plain));
  CHECK(area_distortion(m, balanced) < 0.8 * area_distortion(m, plain));
}

TEST_CASE("cotan weights on a mesh with very obtuse triangles are reported, not silently wrong") {
  // A sphere whose vertices are pulled towards one pole has skinny triangles; either the map is
  // bijective or the error names the flipped triangles.
  auto sphere = test::cube_sphere(6);
  for (int i = 0; i < sphere.num_vertices(); ++i) sphere.positions(i, 2) = std::pow(std::abs(sphere.positions(i, 2)), 0.2) * (sphere.positions(i, 2) < 0 ? -1 : 1);
  const auto m = mesh::HalfedgeMesh::build(sphere, "squashed");
  const auto layout = polycube::compute_cuboid_layout(m);
  param::CuboidSurfaceMapOptions options;
  options.weights = param::SurfaceWeights::Cotan;
  try {
    const auto map = param::compute_cuboid_surface_map(m, layout, options);
    CHECK(map.num_flipped == 0);
  } catch (const Error& e) {
    const std::string what = e.what();
    CHECK((what.find("not bijective") != std::string::npos || what.find("SPD") != std::string::npos));
    CHECK(what.find("squashed") != std::string::npos);
  }
  // Mean-value weights are positive: always bijective.
  CHECK(param::compute_cuboid_surface_map(m, layout).num_flipped == 0);
}

TEST_CASE("the multigrid and IC(0) solvers give the same area-balanced map") {
  const mesh::TriangleMesh bumpy = bumpy_cube_sphere(24);
  const auto m = mesh::HalfedgeMesh::build(bumpy, "bumpy");
  const auto layout = polycube::compute_cuboid_layout(m);
  param::CuboidSurfaceMapOptions options;
  options.area_balance_iterations = 4;
  options.balance_tolerance = options.tolerance;
  const auto multigrid = param::compute_cuboid_surface_map(m, layout, options);
  options.solver = param::SurfaceSolver::IncompleteCholesky;
  const auto ic = param::compute_cuboid_surface_map(m, layout, options);
  CHECK(multigrid.num_flipped == 0);
  CHECK(multigrid.face_region == ic.face_region);
  // Both stop at relative residual 1e-10; the rounds amplify the difference a little.
  CHECK((multigrid.uvw - ic.uvw).cwiseAbs().maxCoeff() <= 1e-7);
  CHECK(multigrid.cg_iterations < ic.cg_iterations);
}

TEST_CASE("looser area-balancing rounds change the final map little; bad tolerances are refused") {
  const mesh::TriangleMesh bumpy = bumpy_cube_sphere(16);
  const auto m = mesh::HalfedgeMesh::build(bumpy, "bumpy");
  const auto layout = polycube::compute_cuboid_layout(m);
  param::CuboidSurfaceMapOptions options;
  options.area_balance_iterations = 4;
  const auto loose = param::compute_cuboid_surface_map(m, layout, options);
  options.balance_tolerance = options.tolerance;
  const auto tight = param::compute_cuboid_surface_map(m, layout, options);
  CHECK(loose.num_flipped == 0);
  // The weights differ by the rounds' residuals (1e-8 relative), the maps by about as much.
  CHECK((loose.uvw - tight.uvw).cwiseAbs().maxCoeff() <= 1e-7);
  CHECK((loose.uvw - tight.uvw).cwiseAbs().maxCoeff() > 0.0);
  for (double bad : {0.0, 1.0, 1e-12}) {
    options.balance_tolerance = bad;
    CHECK_THROWS_WITH_AS(param::compute_cuboid_surface_map(m, layout, options),
                         doctest::Contains("`balance_tolerance`"), Error);
  }
}

TEST_CASE("the squeeze rescue gives a thin tip room, keeps the map bijective and leaves roomy maps alone") {
  // Armadillo with the corners mesh2spline picks for it: its ears, tail and claws are tips that
  // four balancing rounds leave crowded (linear density down to 1e-4).
  const mesh::TriangleMesh armadillo = io::read_mesh(std::string(VOLSPLINE_SHARED_DATA) + "/meshes/armadillo.off");
  const auto m = mesh::HalfedgeMesh::build(armadillo, "armadillo");
  polycube::CuboidLayoutOptions corners;
  corners.corners = {29657, 2563, 36089, 5837, 7561, 3627, 29878, 16029};
  const auto layout = polycube::compute_cuboid_layout(m, corners);
  param::CuboidSurfaceMapOptions options;
  options.area_balance_iterations = 4;
  const auto balanced = param::compute_cuboid_surface_map(m, layout, options);
  CHECK(balanced.squeeze_rounds == 0);
  CAPTURE(balanced.least_density);
  REQUIRE(balanced.least_density < 0.01);
  options.squeezed_below = 0.1;
  const auto rescued = param::compute_cuboid_surface_map(m, layout, options);
  CHECK(rescued.num_flipped == 0);
  CHECK(rescued.squeeze_rounds > 0);
  CHECK(rescued.squeeze_rounds <= options.squeezed_rounds);
  CHECK(rescued.least_density >= 0.1);
  for (const auto& path : layout.poly_edges)
    for (int v : path) CHECK(rescued.uvw.row(v) == balanced.uvw.row(v));

  // A map whose every vertex has room is the balanced one, bit for bit.
  const auto sphere = mesh::HalfedgeMesh::build(test::cube_sphere(12), "sphere");
  const auto sphere_layout = polycube::compute_cuboid_layout(sphere);
  options.squeezed_below = 0.0;
  const auto off = param::compute_cuboid_surface_map(sphere, sphere_layout, options);
  options.squeezed_below = 0.1;
  const auto on = param::compute_cuboid_surface_map(sphere, sphere_layout, options);
  CHECK(off.least_density > 0.1);
  CHECK(on.squeeze_rounds == 0);
  CHECK(on.uvw == off.uvw);

  for (double bad : {-0.1, 1.0}) {
    options.squeezed_below = bad;
    CHECK_THROWS_WITH_AS(param::compute_cuboid_surface_map(sphere, sphere_layout, options),
                         doctest::Contains("`squeezed_below`"), Error);
  }
  options.squeezed_below = 0.1;
  options.squeezed_rounds = 41;
  CHECK_THROWS_WITH_AS(param::compute_cuboid_surface_map(sphere, sphere_layout, options),
                       doctest::Contains("`squeezed_rounds`"), Error);
}
