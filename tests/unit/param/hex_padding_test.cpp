// SPDX-License-Identifier: MIT
#include "core/param/hex_padding.h"

#include <complex>
#include <map>

#include <doctest/doctest.h>

#include "core/mesh/hex_quality.h"
#include "core/param/hex_grid_untangling.h"
#include "core/param/surface_distance.h"

using namespace volspline;

namespace {

// Hexes of an n0×n1×n2 node grid (node i + n0·(j + n1·k)) and the mask of their faces on the
// grid's faces listed in `surface` (bit f: axis f/2 at its low end if f%2 = 0, else its high end).
struct Grid {
  std::vector<std::array<int, 8>> hexes;
  std::vector<int> group;
  std::vector<std::uint8_t> faces;
};
Grid grid_hexes(const std::array<int, 3>& n, int surface) {
  Grid g;
  for (int k = 0; k + 1 < n[2]; ++k)
    for (int j = 0; j + 1 < n[1]; ++j)
      for (int i = 0; i + 1 < n[0]; ++i) {
        std::array<int, 8> hex;
        for (int q = 0; q < 8; ++q) hex[q] = (i + (q & 1)) + n[0] * ((j + (q >> 1 & 1)) + n[1] * (k + (q >> 2 & 1)));
        g.hexes.push_back(hex);
        g.group.push_back(0);
        const std::array<int, 3> ijk = {i, j, k};
        std::uint8_t mask = 0;
        for (int f = 0; f < 6; ++f)
          if ((surface >> f & 1) && (f % 2 == 0 ? ijk[f / 2] == 0 : ijk[f / 2] == n[f / 2] - 2)) mask |= 1 << f;
        g.faces.push_back(mask);
      }
  return g;
}

mesh::Positions unit_cube_nodes(int n) {
  mesh::Positions xyz(n * n * n, 3);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) xyz.row(i + n * (j + n * k)) << double(i) / (n - 1), double(j) / (n - 1), double(k) / (n - 1);
  return xyz;
}

}  // namespace

TEST_CASE("hex padding: a cube grid gets one layer with a copy per surface node") {
  const int n = 3;
  const Grid g = grid_hexes({n, n, n}, 0x3f);
  const param::HexMesh padded = param::pad_hex_mesh(unit_cube_nodes(n), g.hexes, g.group, g.faces, 0.5);
  // 26 of the 27 nodes are on the surface: 26 copies; 6 faces × 4 quads padding hexes.
  CHECK(padded.xyz.rows() == 27 + 26);
  CHECK(padded.hexes.size() == 8 + 24);
  int padding = 0, surface = 0;
  for (char p : padded.padding) padding += p;
  for (char s : padded.on_surface) surface += s;
  CHECK(padding == 24);
  CHECK(surface == 26);
  // The input hexes no longer touch the surface; every padding hex has exactly 4 surface nodes.
  for (std::size_t h = 0; h < padded.hexes.size(); ++h) {
    int on = 0;
    for (int v : padded.hexes[h]) on += padded.on_surface[v];
    CHECK(on == (padded.padding[h] ? 4 : 0));
  }
  // Each surface edge along a cube edge now lies in 2 hexes (one per face) instead of 1.
  std::map<std::pair<int, int>, int> edge_hexes;
  for (const auto& hex : padded.hexes)
    for (int q = 0; q < 8; ++q)
      for (int a = 0; a < 3; ++a)
        if (!(q >> a & 1) && padded.on_surface[hex[q]] && padded.on_surface[hex[q | 1 << a]])
          ++edge_hexes[{std::min(hex[q], hex[q | 1 << a]), std::max(hex[q], hex[q | 1 << a])}];
  CHECK(edge_hexes[{0, 1}] == 2);  // nodes (0,0,0)–(1,0,0): on the cube edge j = k = 0
  const param::HexMeshQuality q = param::hex_mesh_quality(padded);
  CHECK(q.num_inverted == 0);
  CHECK(q.min_scaled_jacobian > 0.3);
}

TEST_CASE("hex padding: a cube edge on a flat surface folds without padding and not with it") {
  // z² maps the quarter plane onto the half plane: the grid's edge u = v = 0 lands on the flat
  // line y = 0 with its two faces at 180°, so the corner there has det J = 0 whatever the
  // interior nodes do.
  const std::array<int, 3> n = {5, 5, 3};
  mesh::Positions xyz(n[0] * n[1] * n[2], 3);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::complex<double> z(1.0 + 0.25 * i, 0.25 * j);
        const std::complex<double> w = z * z - 2.0 * z + 1.0;  // (z − 1)²: the corner (1, 0) at 0
        xyz.row(i + n[0] * (j + n[1] * k)) << w.real(), w.imag(), 0.5 * k;
      }
  const int surface = 1 << 0 | 1 << 2;  // faces u = 0 and v = 0: the line y = 0
  const Grid g = grid_hexes(n, surface);
  param::HexMesh plain;
  plain.xyz = xyz;
  plain.hexes = g.hexes;
  CHECK(param::hex_mesh_quality(plain).num_inverted == n[2] - 1);  // the hexes along the edge
  param::HexMesh padded = param::pad_hex_mesh(xyz, g.hexes, g.group, g.faces, 0.5);
  std::vector<char> fixed(padded.xyz.rows(), 0);
  for (int v = 0; v < padded.xyz.rows(); ++v) {
    fixed[v] = padded.on_surface[v];
    if (v < xyz.rows()) {  // the grid's other faces are held too
      const int i = v % n[0], j = v / n[0] % n[1], k = v / (n[0] * n[1]);
      fixed[v] = fixed[v] || i == n[0] - 1 || j == n[1] - 1 || k == 0 || k == n[2] - 1;
    }
  }
  for (int v = static_cast<int>(xyz.rows()); v < padded.xyz.rows(); ++v) {
    // Copies on the grid's held faces k = 0, k = n2 − 1 stay in those planes: hold them too.
    const double z = padded.xyz(v, 2);
    fixed[v] = std::abs(z) < 1e-12 || std::abs(z - 0.5 * (n[2] - 1)) < 1e-12;
  }
  param::untangle_hex_mesh(padded.hexes, fixed, padded.xyz);
  CHECK(param::hex_mesh_quality(padded).num_inverted == 0);
  // The surface did not move.
  for (int v = 0; v < xyz.rows(); ++v)
    if (padded.on_surface[v]) CHECK((padded.xyz.row(v) - xyz.row(v)).norm() == 0.0);
}

TEST_CASE("untangle_hex_mesh: sliding nodes unfold a folded surface quad and stay on the surface") {
  // A 2×2×1 hex slab whose bottom centre node sits past the middle of its row: the bottom quads
  // on one side are not convex, and no position of the top nodes unfolds their hexes.
  const std::array<int, 3> n = {3, 3, 2};
  mesh::Positions xyz(18, 3);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) xyz.row(i + 3 * (j + 3 * k)) << i, j, k;
  const int centre = 1 + 3 * 1;
  xyz.row(centre) << 1.0, 2.3, 0.0;
  const mesh::Positions start = xyz;
  const Grid g = grid_hexes(n, 0);
  param::HexMesh mesh;
  mesh.xyz = xyz;
  mesh.hexes = g.hexes;
  REQUIRE(param::hex_mesh_quality(mesh).num_inverted > 0);
  std::vector<char> fixed(18, 1);
  fixed[1 + 3 * (1 + 3)] = 0;  // the top centre node is free
  mesh::Positions held = xyz;
  param::untangle_hex_mesh(mesh.hexes, fixed, held);
  mesh.xyz = held;
  CHECK(param::hex_mesh_quality(mesh).num_inverted > 0);
  // The bottom centre slides on the plane z = 0.
  fixed[centre] = 0;
  param::SlidingNodes sliding;
  sliding.slides.assign(18, 0);
  sliding.slides[centre] = 1;
  sliding.project = [](int, const Eigen::Vector3d& p, Eigen::Matrix3d* tangent) {
    if (tangent) *tangent = Eigen::Vector3d(1.0, 1.0, 0.0).asDiagonal();
    return Eigen::Vector3d(p.x(), p.y(), 0.0);
  };
  param::untangle_hex_mesh(mesh.hexes, fixed, xyz, {}, {}, &sliding);
  mesh.xyz = xyz;
  CHECK(param::hex_mesh_quality(mesh).num_inverted == 0);
  CHECK(xyz(centre, 2) == 0.0);
  // improve_hex_mesh keeps it fold-free and does not lower the worst corner.
  const double before = param::hex_mesh_quality(mesh).min_scaled_jacobian;
  CHECK(param::improve_hex_mesh(mesh.hexes, fixed, xyz, 50, 0.5, &sliding) > 0);
  mesh.xyz = xyz;
  CHECK(param::hex_mesh_quality(mesh).num_inverted == 0);
  CHECK(param::hex_mesh_quality(mesh).min_scaled_jacobian >= before - 1e-12);
  CHECK(xyz(centre, 2) == 0.0);
  // With the sliding unknowns set onto the surface after every step: unfolded too, on the plane.
  param::HexGridUntangleOptions settled;
  settled.settle_sliding = true;
  mesh::Positions again = start, folded = start;
  const param::HexGridUntangleReport report = param::untangle_hex_mesh(mesh.hexes, fixed, again, {}, settled, &sliding);
  CHECK(report.initial_inverted > 0);
  CHECK(report.final_inverted == 0);
  mesh.xyz = again;
  CHECK(param::hex_mesh_quality(mesh).num_inverted == 0);
  CHECK(again(centre, 2) == 0.0);
  // Deterministic.
  param::untangle_hex_mesh(mesh.hexes, fixed, folded, {}, settled, &sliding);
  CHECK(folded == again);
}

TEST_CASE("surface distance: the closest point and its triangle's normal") {
  mesh::TriangleMesh m;
  m.positions.resize(4, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0;
  m.triangles.resize(2, 3);
  m.triangles << 0, 1, 2, 1, 3, 2;
  const param::SurfaceDistance d(m);
  Eigen::Vector3d normal;
  const Eigen::Vector3d q = d.closest_point(Eigen::Vector3d(0.75, 0.6, 2.0), &normal);
  CHECK((q - Eigen::Vector3d(0.75, 0.6, 0.0)).norm() < 1e-15);
  CHECK((normal - Eigen::Vector3d::UnitZ()).norm() < 1e-15);
  // Outside the square: its nearest edge point.
  CHECK((d.closest_point(Eigen::Vector3d(2.0, 0.5, -1.0)) - Eigen::Vector3d(1.0, 0.5, 0.0)).norm() < 1e-15);
}
