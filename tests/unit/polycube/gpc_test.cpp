// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <set>

#include "core/common/error.h"
#include "core/io/gpc_json.h"
#include "core/io/mesh_io.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_geometry.h"
#include "core/mesh/mesh_lists.h"
#include "core/mesh/mesh_report.h"
#include "core/param/cuboid_surface_map.h"
#include "core/param/gpc_volumetric_map.h"
#include "core/pipeline/gpc_job.h"
#include "core/polycube/cuboid_layout.h"
#include "core/polycube/cut_flips.h"
#include "core/polycube/cylinder_map.h"
#include "core/polycube/gpc_builder.h"
#include "core/polycube/disc_chords.h"
#include "core/polycube/gpc_domain.h"
#include "core/polycube/interface_disc.h"
#include "core/polycube/level_set_split.h"
#include "core/polycube/morse_function.h"
#include "core/polycube/solid_decomposition.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

// Torus with major radius 1 and minor radius r around the z axis, nu × nv quads split in two.
mesh::TriangleMesh make_torus(int nu, int nv, double r = 0.35) { return test::torus(nu, nv, 1.0, r); }

// A "T" of voxels (a bar of 7 cells and a stem of 4 under its middle, one cell thick): genus 0
// with three limbs.
mesh::TriangleMesh make_t_solid(int k) {
  return test::voxel_solid(7, 5, 1, k, [](int x, int y, int) { return y == 4 || x == 3; });
}

// The boundary of {sdf < 0} on an n³ grid over [−half, half]³ by marching tetrahedra (6 per
// cube along its main diagonal, so neighbouring cubes match): a closed manifold when no grid value
// is 0; triangles oriented from the inside to the outside.
template <class Sdf>
mesh::TriangleMesh marching_tetrahedra(const Sdf& sdf, int n, double half) {
  const double h = 2.0 * half / n;
  auto grid_id = [&](int i, int j, int k) { return (static_cast<long>(i) * (n + 1) + j) * (n + 1) + k; };
  auto grid_xyz = [&](long id) {
    const int k = static_cast<int>(id % (n + 1)), j = static_cast<int>(id / (n + 1) % (n + 1)),
              i = static_cast<int>(id / ((n + 1) * (n + 1)));
    return Eigen::Vector3d(-half + i * h, -half + j * h, -half + k * h);
  };
  std::map<long, double> value_cache;
  auto value = [&](long id) {
    auto it = value_cache.find(id);
    if (it != value_cache.end()) return it->second;
    double s = sdf(grid_xyz(id));
    if (std::abs(s) < 1e-9) s = 1e-9;
    return value_cache[id] = s;
  };
  std::map<std::pair<long, long>, int> edge_vertex;
  std::vector<Eigen::Vector3d> pts;
  auto crossing = [&](long a, long b) {
    const std::pair<long, long> key{std::min(a, b), std::max(a, b)};
    auto it = edge_vertex.find(key);
    if (it != edge_vertex.end()) return it->second;
    const double fa = value(key.first), fb = value(key.second);
    // Kept off the grid points, so that no triangle degenerates.
    const double t = std::clamp(fa / (fa - fb), 0.05, 0.95);
    pts.push_back(grid_xyz(key.first) + t * (grid_xyz(key.second) - grid_xyz(key.first)));
    return edge_vertex[key] = static_cast<int>(pts.size()) - 1;
  };
  std::vector<std::array<int, 3>> tris;
  auto emit = [&](int a, int b, int c, const Eigen::Vector3d& outward_dir) {
    if ((pts[b] - pts[a]).cross(pts[c] - pts[a]).dot(outward_dir) < 0) std::swap(b, c);
    tris.push_back({a, b, c});
  };
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        for (const auto& perm : perms) {
          std::array<long, 4> tet;
          std::array<int, 3> c = {i, j, k};
          tet[0] = grid_id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[perm[s]];
            tet[s + 1] = grid_id(c[0], c[1], c[2]);
          }
          std::vector<long> in, out;
          for (long v : tet) (value(v) < 0 ? in : out).push_back(v);
          if (in.empty() || out.empty()) continue;
          Eigen::Vector3d ci = Eigen::Vector3d::Zero(), co = Eigen::Vector3d::Zero();
          for (long v : in) ci += grid_xyz(v) / static_cast<double>(in.size());
          for (long v : out) co += grid_xyz(v) / static_cast<double>(out.size());
          const Eigen::Vector3d dir = co - ci;
          if (in.size() == 1 || out.size() == 1) {
            const long apex = in.size() == 1 ? in[0] : out[0];
            const std::vector<long>& rest = in.size() == 1 ? out : in;
            emit(crossing(apex, rest[0]), crossing(apex, rest[1]), crossing(apex, rest[2]), dir);
          } else {
            const int a = crossing(in[0], out[0]), b = crossing(in[0], out[1]), c1 = crossing(in[1], out[1]),
                      d = crossing(in[1], out[0]);
            emit(a, b, c1, dir);
            emit(a, c1, d, dir);
          }
        }
  return test::mesh_of(pts, tris);
}

// A frame of genus 3 shaped as the planar drawing of a tetrahedron's edges: the triangle
// (−1, −0.6, 0), (1, −0.6, 0), (0, 0.9, 0) with a centre (0, −0.1, 0) joined to its corners, the
// spoke to the top corner bent into an arch of height `arch` over the plane z = 0; tubes of
// radius r, on an n³ grid over [−1.5, 1.5]³.
mesh::TriangleMesh make_arched_frame(int n, double r, double arch) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
  const Eigen::Vector3d p0(-1, -0.6, 0), p1(1, -0.6, 0), p2(0, 0.9, 0), q(0, -0.1, 0);
  segments.push_back({p0, p1});
  segments.push_back({p0, p2});
  segments.push_back({p1, p2});
  segments.push_back({q, p0});
  segments.push_back({q, p1});
  const double pi = 3.14159265358979323846;
  const int steps = 12;
  auto on_arch = [&](int i) {
    const double t = double(i) / steps;
    return Eigen::Vector3d(0, -0.1 + t, arch * std::sin(pi * t));
  };
  for (int i = 0; i < steps; ++i) segments.push_back({on_arch(i), on_arch(i + 1)});
  auto sdf = [&](const Eigen::Vector3d& p) {
    double d = 1e300;
    for (const auto& [a, b] : segments) {
      const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      d = std::min(d, (a + t * (b - a) - p).norm() - r);
    }
    return d;
  };
  return marching_tetrahedra(sdf, n, 1.5);
}

// A pipe around the z axis (genus 1): radii 0.45 to 0.75, height 2·half_height, rounded outside.
// Taller than wide, the Morse function's levels run around the axis (longitudes).
mesh::TriangleMesh make_pipe(int n, double half_height) {
  auto sdf = [&](const Eigen::Vector3d& p) {
    const double qx = std::abs(std::hypot(p.x(), p.y()) - 0.6) - 0.15, qz = std::abs(p.z()) - half_height;
    return std::hypot(std::max(qx, 0.0), std::max(qz, 0.0)) + std::min(std::max(qx, qz), 0.0);
  };
  return marching_tetrahedra(sdf, n, 1.45);
}

// A square plate with 2 × 2 round holes (genus 4): bars of about square cross-section in a 3 × 3
// lattice, on an n³ grid over [−1.5, 1.5]³.
mesh::TriangleMesh make_holed_plate(int n) {
  auto sdf = [](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = p.cwiseAbs() - Eigen::Vector3d(1.3, 1.3, 0.22);
    double d = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0) - 0.08;
    for (double x : {-0.6, 0.6})
      for (double y : {-0.6, 0.6}) d = std::max(d, 0.33 - std::hypot(p.x() - x, p.y() - y));
    return d;
  };
  return marching_tetrahedra(sdf, n, 1.5);
}

// A k × k grid on the unit square (columns at x_of(i), rows at j / k), lifted onto a paraboloid.
mesh::TriangleMesh paraboloid_disc(int k, const std::function<double(int)>& x_of) {
  mesh::TriangleMesh m;
  m.positions.resize((k + 1) * (k + 1), 3);
  for (int j = 0; j <= k; ++j)
    for (int i = 0; i <= k; ++i) {
      const double x = x_of(i), y = double(j) / k;
      m.positions.row(j * (k + 1) + i) << x, y, 0.3 * (x * x + y * y);
    }
  m.triangles.resize(2 * k * k, 3);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      const int a = j * (k + 1) + i, b = a + 1, c = a + k + 2, d = a + k + 1;
      m.triangles.row(2 * (j * k + i)) << a, b, c;
      m.triangles.row(2 * (j * k + i) + 1) << a, c, d;
    }
  return m;
}

// A small volumetric grid: the domain tests below do not measure the grid, and it dominates
// their time (most of all under the sanitizers).
pipeline::GpcOptions small_grid() {
  pipeline::GpcOptions o;
  o.grid.target_nodes = 3000;
  return o;
}

// For the tests of what the job builds before its volumetric grids (decomposition, cuboids,
// glued faces, surface maps): the grids keep the harmonic map's folds, as with gpc --no-untangle.
pipeline::GpcOptions without_untangling() {
  pipeline::GpcOptions o = small_grid();
  o.grid.untangle = param::GpcGridOptions::Untangle::Off;
  return o;
}

// The decomposition's caps and T-shapes.
struct PieceCounts {
  int caps = 0, t_shapes = 0;
};
PieceCounts count_pieces(const polycube::SolidDecomposition& d) {
  PieceCounts c;
  for (const auto& p : d.pieces) {
    c.caps += p.kind == polycube::PieceKind::Cap;
    c.t_shapes += p.kind == polycube::PieceKind::TShape;
  }
  return c;
}

mesh::HalfedgeMesh outward(const mesh::TriangleMesh& m) {
  mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(m, "test");
  if (mesh::analyze_mesh(hm).signed_volume < 0) {
    mesh::TriangleMesh f = m;
    f.triangles.col(1).swap(f.triangles.col(2));
    return mesh::HalfedgeMesh::build(f, "test");
  }
  return hm;
}

}  // namespace

TEST_CASE("level-set split: every triangle lies on one side of the level") {
  const mesh::TriangleMesh torus = make_torus(24, 12);
  std::vector<double> f(torus.num_vertices());
  for (int v = 0; v < torus.num_vertices(); ++v) f[v] = torus.positions(v, 0);
  const polycube::LevelSetSplit s = polycube::split_at_level(torus, f, {}, 0.1234);
  CHECK(s.mesh.num_faces() > torus.num_faces());
  for (int t = 0; t < s.mesh.num_faces(); ++t) {
    bool below = false, above = false;
    for (int k = 0; k < 3; ++k) {
      below = below || s.value[s.mesh.triangles(t, k)] < 0.1234;
      above = above || s.value[s.mesh.triangles(t, k)] > 0.1234;
    }
    CHECK_FALSE((below && above));
  }
  const mesh::MeshReport r = mesh::analyze_mesh(mesh::HalfedgeMesh::build(s.mesh, "split"));
  CHECK(r.closed);
  CHECK(r.genus == 1);
}

TEST_CASE("Morse decomposition: a torus is one tube closed on itself, a two-hole solid two T-shapes") {
  const mesh::HalfedgeMesh torus = outward(make_torus(32, 16));
  const polycube::SolidDecomposition d = polycube::decompose_solid(torus, 1);
  CHECK(d.num_saddles == 2);
  REQUIRE(d.pieces.size() == 1);
  CHECK(d.pieces[0].kind == polycube::PieceKind::Tube);
  REQUIRE(d.loops.size() == 1);
  CHECK(d.loops[0].piece[0] == d.loops[0].piece[1]);

  const mesh::HalfedgeMesh slab = outward(test::two_hole_slab(3));
  REQUIRE(mesh::analyze_mesh(slab).genus == 2);
  const polycube::SolidDecomposition e = polycube::decompose_solid(slab, 2);
  CHECK(e.num_saddles == 4);
  const auto [caps, tshapes] = count_pieces(e);
  CHECK(tshapes == caps + 2 * 2 - 2);  // Euler characteristic count
  CHECK(e.loops.size() == 3);
}

TEST_CASE("meridian certificate: a meridian disc is inside the torus, the hole's disc is not") {
  const mesh::TriangleMesh torus = make_torus(32, 16);
  const int nv = 16;
  std::vector<int> meridian, inner;
  for (int j = 0; j < nv; ++j) meridian.push_back(j);              // i = 0: a cross-section
  for (int i = 0; i < 32; ++i) inner.push_back(i * nv + nv / 2);  // b = π: the inner equator
  auto disc_of = [&](const std::vector<int>& loop) {
    mesh::Positions xyz(static_cast<int>(loop.size()), 3);
    for (std::size_t i = 0; i < loop.size(); ++i) xyz.row(static_cast<int>(i)) = torus.positions.row(loop[i]);
    return polycube::triangulate_interface_disc(xyz);
  };
  const auto good = polycube::check_interface_discs(torus, {disc_of(meridian)}, {meridian});
  CHECK(good.num_intersections == 0);
  CHECK(good.num_outside == 0);
  CHECK(good.winding[0] == doctest::Approx(1.0).epsilon(1e-6));
  const auto bad = polycube::check_interface_discs(torus, {disc_of(inner)}, {inner});
  CHECK(bad.num_outside == 1);
}

TEST_CASE("Morse decomposition: an arched frame is cut along meridians only, one loop re-split") {
  // The arched spoke lies along a level of the Morse function: the naive cut between its two
  // junctions runs along the arch and its disc lies under it, outside the solid. The
  // decomposition replaces that cut (resplit_across_loop): 4 T-shapes, 6 cuts, every disc inside.
  const mesh::HalfedgeMesh frame = outward(make_arched_frame(40, 0.2, 0.6));
  REQUIRE(mesh::analyze_mesh(frame).genus == 3);
  const polycube::SolidDecomposition d = polycube::decompose_solid(frame, 3);
  CHECK(d.num_saddles == 6);
  CHECK(d.num_resplit_cuts == 1);
  int tshapes = 0;
  for (const auto& p : d.pieces) tshapes += p.kind == polycube::PieceKind::TShape;
  CHECK(tshapes == 4);
  REQUIRE(d.loops.size() == 6);
  const mesh::MeshReport cut = mesh::analyze_mesh(mesh::HalfedgeMesh::build(d.mesh, "cut"));
  CHECK(cut.closed);
  CHECK(cut.genus == 3);
  // Each piece lists exactly the loop sides that name it.
  for (std::size_t p = 0; p < d.pieces.size(); ++p)
    for (const polycube::LoopSide& b : d.pieces[p].boundary)
      CHECK(d.loops[b.loop].piece[b.side] == static_cast<int>(p));
  for (const polycube::CutLoop& loop : d.loops) {
    const polycube::DiscEmbedding e = polycube::check_loop_disc(d.mesh, loop.vertices);
    CHECK(e.winding[0] == doctest::Approx(1.0).epsilon(1e-3));  // solid angles of a closed surface
  }
}

TEST_CASE("gpc job: the arched frame is 4 T-shapes with Type-1 ill-points only, its cut discs inside") {
  // The two-pole construction (on this coarse surface a spot of its maps is squeezed below
  // pole_caps_below, and the retry with caps at the poles is kept: 2 caps, 6 T-shapes).
  pipeline::GpcOptions o = without_untangling();
  o.pole_caps_below = 0.0;
  const pipeline::GpcResult r = pipeline::run_gpc(make_arched_frame(40, 0.2, 0.6), "frame", o);
  CHECK(r.stats.genus == 3);
  CHECK(r.stats.t_shapes == 4);
  CHECK(r.stats.cut_discs_outside == 0);
  CHECK(r.stats.flipped_triangles == 0);
  for (const auto& p : r.construction.domain.ill_points) CHECK(p.type == 1);
}

TEST_CASE("Morse decomposition: a tall pipe's longitude cut is replaced by a meridian") {
  const mesh::HalfedgeMesh pipe = outward(make_pipe(32, 1.0));
  REQUIRE(mesh::analyze_mesh(pipe).genus == 1);
  const polycube::SolidDecomposition d = polycube::decompose_solid(pipe, 1);
  CHECK(d.num_resplit_cuts == 1);
  REQUIRE(d.pieces.size() == 1);
  CHECK(d.pieces[0].kind == polycube::PieceKind::Tube);
  REQUIRE(d.loops.size() == 1);
  const polycube::CutLoop& loop = d.loops[0];
  CHECK(loop.piece[0] == loop.piece[1]);
  CHECK(polycube::check_loop_disc(d.mesh, loop.vertices).winding[0] == doctest::Approx(1.0).epsilon(1e-3));
  // A meridian goes around the wall: up the outside, down the inside, at one angle about the axis.
  double z_lo = 1e300, z_hi = -1e300, r_lo = 1e300, r_hi = -1e300;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int v : loop.vertices) {
    const Eigen::RowVector3d x = d.mesh.positions.row(v);
    z_lo = std::min(z_lo, x(2));
    z_hi = std::max(z_hi, x(2));
    r_lo = std::min(r_lo, std::hypot(x(0), x(1)));
    r_hi = std::max(r_hi, std::hypot(x(0), x(1)));
    mean += Eigen::Vector2d(x(0), x(1)).normalized();
  }
  CHECK(z_hi - z_lo > 1.8);
  CHECK(r_lo < 0.5);
  CHECK(r_hi > 0.7);
  for (int v : loop.vertices)
    CHECK(Eigen::Vector2d(d.mesh.positions(v, 0), d.mesh.positions(v, 1)).normalized().dot(mean.normalized()) > 0.9);
  const pipeline::GpcResult r = pipeline::run_gpc(make_pipe(32, 1.0), "pipe", without_untangling());
  CHECK(r.stats.cuboids == 1);
  CHECK(r.stats.tubes == 1);
  CHECK(r.stats.cut_discs_outside == 0);
  CHECK(r.stats.flipped_triangles == 0);
}

TEST_CASE("cylinder map: u runs from loop to loop, v around") {
  // The torus cut at i = 0 and i = 12 gives an annulus: take faces with i in [0, 12).
  const mesh::TriangleMesh torus = make_torus(24, 12);
  mesh::TriangleMesh band;
  band.positions = torus.positions;
  std::vector<std::array<int, 3>> tris;
  for (int t = 0; t < torus.num_faces(); ++t) {
    const int i = t / 24;  // 2 triangles per quad, 12 quads per ring
    if (i < 12) tris.push_back({torus.triangles(t, 0), torus.triangles(t, 1), torus.triangles(t, 2)});
  }
  band.triangles = mesh::triangles_from(tris);
  // Drop vertices no face uses by keeping them: HalfedgeMesh allows unreferenced vertices.
  const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(band, "band");
  std::vector<int> a, b;
  for (int j = 0; j < 12; ++j) {
    a.push_back(j);
    b.push_back(12 * 12 + j);
  }
  const polycube::CylinderMap cyl = polycube::compute_cylinder_map(hm, a, b);
  for (int j = 0; j < 12; ++j) {
    CHECK(cyl.u[a[j]] == doctest::Approx(0.0));
    CHECK(cyl.u[b[j]] == doctest::Approx(1.0));
  }
  // Along a longitude u grows monotonically.
  for (int i = 1; i <= 12; ++i) CHECK(cyl.u[i * 12 + 3] > cyl.u[(i - 1) * 12 + 3]);
  CHECK(cyl.circumference > 0.0);
}

TEST_CASE("transition maps: corner gluing, inverse and composition") {
  // Face x = 1 of A (size 2×1×1) on face x = 0 of B (size 1×1×1), corners in the same order.
  polycube::GpcTransition t;
  const std::array<int, 4> ca = polycube::cube_face_corners(1), cb = polycube::cube_face_corners(0);
  REQUIRE(polycube::gpc_transition_from_corners(1, {2, 1, 1}, ca, 0, {1, 1, 1}, cb, t));
  CHECK(t.apply(Eigen::Vector3d(2, 0.5, 0.25)).isApprox(Eigen::Vector3d(0, 0.5, 0.25)));
  CHECK(t.apply(Eigen::Vector3d(1.5, 0, 0)).isApprox(Eigen::Vector3d(-0.5, 0, 0)));
  const polycube::GpcTransition id = t.inverse().after(t);
  CHECK(id.axis == std::array<int, 3>{0, 1, 2});
  CHECK(id.sign == std::array<int, 3>{1, 1, 1});
  CHECK(id.translation.norm() < 1e-15);
  // A quarter turn about the face normal is a rotation too; a mirrored order is not.
  const std::array<int, 4> turned = {cb[1], cb[2], cb[3], cb[0]};
  CHECK(polycube::gpc_transition_from_corners(1, {1, 1, 1}, ca, 0, {1, 1, 1}, turned, t));
  const std::array<int, 4> mirrored = {cb[0], cb[3], cb[2], cb[1]};
  CHECK_FALSE(polycube::gpc_transition_from_corners(1, {1, 1, 1}, ca, 0, {1, 1, 1}, mirrored, t));
}

TEST_CASE("gpc job: a torus is 1 cuboid glued to itself, fold-free, glued nodes shared exactly") {
  const pipeline::GpcResult r = pipeline::run_gpc(make_torus(40, 16), "torus");
  const pipeline::GpcStats& s = r.stats;
  CHECK(s.genus == 1);
  CHECK(s.cuboids == 1);
  CHECK(s.tubes == 1);
  CHECK(s.ill_points == 0);
  CHECK(s.flipped_triangles == 0);
  CHECK(s.grid_inverted_hexes == 0);
  CHECK(s.grid_min_scaled_jacobian > 0.2);
  CHECK(s.interface_gap_rel <= 1e-12);
  CHECK(s.cut_disc_intersections == 0);
  REQUIRE(r.construction.domain.interfaces.size() == 1);
  const polycube::GpcInterface& g = r.construction.domain.interfaces[0];
  CHECK(g.cuboid[0] == 0);
  CHECK(g.cuboid[1] == 0);
  CHECK(std::set<int>{g.face[0], g.face[1]} == std::set<int>{4, 5});
  // Around the handle: the map and its inverse compose to the identity.
  const polycube::GpcTransition id = g.transition.after(g.transition.inverse());
  CHECK(id.translation.norm() < 1e-12);
  // Every copy of a glued node is one node: grid w = 0 and w = 1 coincide through the map.
  const auto& grid = r.map.grids[0];
  CHECK(grid.xyz.rows() == grid.nodes[0] * grid.nodes[1] * grid.nodes[2]);
}

// mesh2spline samples every hex-mesh node at its grid parameter: without face sliding no stage
// may move a surface node off the point the surface map gives its parameter (grid.face_sliding).
// On kitten_coarse the quality step after the untangling moves about half of them if let.
TEST_CASE("gpc job: without face sliding the hex mesh's surface nodes stay where the surface maps put them") {
  pipeline::GpcOptions o;
  o.grid.face_sliding = param::GpcGridOptions::FaceSliding::Off;
  o.grid.padded_reference = param::GpcGridOptions::PaddedReference::MeanCell;
  o.grid.min_quality_sweeps = 0;
  const pipeline::GpcResult r =
      pipeline::run_gpc(io::read_mesh(std::string(VOLSPLINE_SHARED_DATA) + "/meshes/kitten_coarse.off"), "kitten", o);
  REQUIRE(r.stats.grid_inverted_hexes == 0);  // the quality step runs on fold-free meshes only
  // The grids keep their nodes as the surface maps placed them; the padded mesh lists the same
  // nodes first, then their inner copies.
  std::set<std::array<double, 3>> placed;
  for (const param::GpcCuboidGrid& g : r.map.grids)
    for (Eigen::Index k = 0; k < g.xyz.rows(); ++k) placed.insert({g.xyz(k, 0), g.xyz(k, 1), g.xyz(k, 2)});
  const param::HexMesh& hm = r.map.hex_mesh;
  REQUIRE(hm.on_surface.size() == static_cast<std::size_t>(hm.xyz.rows()));
  int surface = 0, moved = 0;
  for (Eigen::Index k = 0; k < hm.xyz.rows(); ++k) {
    if (!hm.on_surface[k]) continue;
    ++surface;
    moved += placed.count({hm.xyz(k, 0), hm.xyz(k, 1), hm.xyz(k, 2)}) == 0;
  }
  CHECK(surface > 1000);
  CHECK(moved == 0);
}

TEST_CASE("gpc job: an elongated cut loop gets its corners near a rectangle's, not at its ends and sides") {
  // A torus whose cross-section is an ellipse three times as wide (radially) as high: its cut
  // loop's vertex farthest from the centroid is at a wide end, and quarters from there put the
  // corners at both ends and the middles of the long sides (a rhombus of 37° corners).
  mesh::TriangleMesh m = make_torus(40, 24, 0.3);
  for (int v = 0; v < m.num_vertices(); ++v) m.positions(v, 2) /= 3.0;
  const pipeline::GpcResult r = pipeline::run_gpc(m, "flat torus");
  CHECK(r.stats.cuboids == 1);
  CHECK(r.stats.grid_inverted_hexes == 0);
  REQUIRE(r.construction.domain.interfaces.size() == 1);
  const polycube::GpcInterface& g = r.construction.domain.interfaces[0];
  const polycube::GpcCuboid& cuboid = r.construction.domain.cuboids[0];
  // The 4 corners of the glued face w = g.face[0] % 2 (cube corner c at (c&1, c>>1&1, c>>2&1)),
  // in order around the face, and the angle between the chords at each.
  const int w = g.face[0] % 2;
  const std::array<int, 4> ring{0, 1, 3, 2};
  double least = 180.0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d p = cuboid.corner_xyz[ring[k] + 4 * w];
    const Eigen::Vector3d a = cuboid.corner_xyz[ring[(k + 3) % 4] + 4 * w] - p;
    const Eigen::Vector3d b = cuboid.corner_xyz[ring[(k + 1) % 4] + 4 * w] - p;
    least = std::min(least, std::acos(a.dot(b) / (a.norm() * b.norm())) * 180.0 / 3.14159265358979323846);
  }
  CHECK(least > 60.0);
}

TEST_CASE("gpc job: position and units do not matter") {
  mesh::TriangleMesh a = make_torus(40, 16), b = a;
  b.positions = (b.positions * 1e-3).rowwise() + Eigen::RowVector3d(1e6, -2e5, 3e4);
  const pipeline::GpcResult ra = pipeline::run_gpc(a, "a"), rb = pipeline::run_gpc(b, "b");
  CHECK(ra.stats.cuboids == rb.stats.cuboids);
  CHECK(ra.stats.grid_nodes == rb.stats.grid_nodes);
  CHECK(ra.stats.grid_inverted_hexes == rb.stats.grid_inverted_hexes);
  // The quality pass is an optimizer: inputs a rounding apart (1e-7 of the size after this move) end
  // a little apart.
  CHECK(ra.stats.grid_min_scaled_jacobian == doctest::Approx(rb.stats.grid_min_scaled_jacobian).epsilon(1e-3));
}

TEST_CASE("gpc job: a genus-0 blob is one cuboid laid out as mesh2spline does") {
  const mesh::TriangleMesh torus = make_torus(24, 12);
  // A genus-0 blob: a squashed sphere from a latitude-longitude grid.
  mesh::TriangleMesh blob;
  const int nu = 24, nv = 12;
  const double pi = 3.14159265358979323846;
  blob.positions.resize(nu * (nv - 1) + 2, 3);
  for (int i = 0; i < nu; ++i)
    for (int j = 1; j < nv; ++j) {
      const double a = 2 * pi * i / nu, b = pi * j / nv;
      blob.positions.row(i * (nv - 1) + j - 1) << 1.5 * std::sin(b) * std::cos(a), std::sin(b) * std::sin(a), 0.8 * std::cos(b);
    }
  const int north = nu * (nv - 1), south = north + 1;
  blob.positions.row(north) << 0, 0, 0.8;
  blob.positions.row(south) << 0, 0, -0.8;
  std::vector<std::array<int, 3>> tris;
  for (int i = 0; i < nu; ++i) {
    const int i1 = (i + 1) % nu;
    tris.push_back({north, i * (nv - 1), i1 * (nv - 1)});
    for (int j = 0; j + 1 < nv - 1; ++j) {
      const int a = i * (nv - 1) + j, b = i1 * (nv - 1) + j;
      tris.push_back({a, a + 1, b + 1});
      tris.push_back({a, b + 1, b});
    }
    tris.push_back({south, i1 * (nv - 1) + nv - 2, i * (nv - 1) + nv - 2});
  }
  blob.triangles = mesh::triangles_from(tris);
  const pipeline::GpcResult r = pipeline::run_gpc(blob, "blob");
  CHECK(r.stats.genus == 0);
  CHECK(r.stats.cuboids == 1);
  CHECK(r.construction.domain.interfaces.empty());
  CHECK(r.stats.flipped_triangles == 0);
  (void)torus;
}

TEST_CASE("GPC JSON: write → read → write is byte-identical; bad files name the problem") {
  const pipeline::GpcResult r = pipeline::run_gpc(make_torus(32, 12), "torus");
  const std::string text = io::serialize_gpc_domain(r.construction.domain);
  const polycube::GpcDomain back = io::parse_gpc_domain(text, "t.json");
  CHECK(io::serialize_gpc_domain(back) == text);
  CHECK_THROWS_WITH(io::parse_gpc_domain("{", "x.json"), doctest::Contains("x.json"));
  CHECK_THROWS_WITH(io::parse_gpc_domain("{\"format\": \"other\"}", "x.json"), doctest::Contains("format"));
}

TEST_CASE("disc chords: straight cuts across a disc become disjoint edge paths") {
  // A 6 × 6 grid on the unit square, lifted onto a paraboloid; corners at the square's corners.
  const int k = 6;
  mesh::TriangleMesh m = paraboloid_disc(k, [&](int i) { return double(i) / k; });
  std::vector<int> region(m.num_faces());
  for (int f = 0; f < m.num_faces(); ++f) region[f] = f;
  const int c00 = 0, c10 = k, c11 = (k + 1) * (k + 1) - 1, c01 = k * (k + 1);
  // Bottom-side vertex 2 to top-side vertex 3, and left-side vertex 1 to right-side vertex 4.
  const int b2 = 2, t3 = k * (k + 1) + 3, l1 = (k + 1), r4 = 4 * (k + 1) + k;
  polycube::DiscChords dc;
  std::string why;
  const mesh::TriangleMesh before = m;
  REQUIRE(polycube::cut_disc_chords(m, region, {c00, c10, c11, c01}, {{{b2, t3}}, {{l1, r4}}}, dc, &why));
  REQUIRE(dc.paths.size() == 2);
  CHECK(dc.paths[0].front() == b2);
  CHECK(dc.paths[0].back() == t3);
  CHECK(dc.paths[1].front() == l1);
  CHECK(dc.paths[1].back() == r4);
  // Crossing chords share exactly one (new) vertex; consecutive path vertices are mesh edges.
  std::set<int> first(dc.paths[0].begin(), dc.paths[0].end());
  int shared = 0;
  for (int v : dc.paths[1]) shared += static_cast<int>(first.count(v));
  CHECK(shared == 1);
  const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(m, "chords");
  const mesh::MeshReport report = mesh::analyze_mesh(hm);
  CHECK(report.num_boundary_loops == 1);
  CHECK(report.consistently_oriented);
  for (const auto& path : dc.paths)
    for (std::size_t i = 1; i < path.size(); ++i) {
      bool adjacent = false;
      for (int h : hm.vertex_outgoing(path[i - 1])) adjacent = adjacent || hm.halfedge_vertex(h) == path[i];
      CHECK(adjacent);
    }
  // Same surface: the area is kept, old vertices did not move, new ones lie on old edges.
  auto area = [](const mesh::TriangleMesh& t) {
    double a = 0.0;
    for (int f = 0; f < t.num_faces(); ++f) {
      const Eigen::Vector3d p = t.positions.row(t.triangles(f, 0)), q = t.positions.row(t.triangles(f, 1)),
                            r = t.positions.row(t.triangles(f, 2));
      a += 0.5 * (q - p).cross(r - p).norm();
    }
    return a;
  };
  CHECK(area(m) == doctest::Approx(area(before)).epsilon(1e-3));
  CHECK((m.positions.topRows(before.num_vertices()) - before.positions).norm() == 0.0);
  CHECK(static_cast<int>(dc.face_origin.size()) == m.num_faces());
  CHECK(static_cast<int>(dc.new_vertex_t.size()) == m.num_vertices() - before.num_vertices());
  // A chord end inside the disc is refused.
  mesh::TriangleMesh again = before;
  CHECK_FALSE(polycube::cut_disc_chords(again, region, {c00, c10, c11, c01}, {{{b2, k + 3}}}, dc, &why));
  CHECK(why.find("boundary") != std::string::npos);
}

TEST_CASE("poly-edge chords: a detour that makes a chord is split, and the face map is bijective again") {
  // One cuboid on a subdivided cube whose poly-edge 0 takes a detour p1 → q → p2 over a
  // neighbouring vertex: the edge p1p2 is then a chord inside the face on the other side, and the
  // triangle p1 q p2 has all three corners on one side of its square.
  const mesh::TriangleMesh cube = test::subdivided_cube(4);
  const auto hm = mesh::HalfedgeMesh::build(cube, "cube");
  const polycube::CuboidLayout automatic = polycube::compute_cuboid_layout(hm);
  std::vector<int> detour = automatic.poly_edges[0];
  REQUIRE(detour.size() == 5);
  const int p1 = detour[1], p2 = detour[2];
  int q = -1;
  for (int f = 0; f < cube.num_faces() && q < 0; ++f) {
    const std::array<int, 3> t = {cube.triangles(f, 0), cube.triangles(f, 1), cube.triangles(f, 2)};
    for (int k = 0; k < 3; ++k)
      if (t[k] == p1 && t[(k + 1) % 3] == p2) q = t[(k + 2) % 3];
  }
  REQUIRE(q >= 0);
  detour.insert(detour.begin() + 2, q);
  polycube::CuboidLayout layout;
  layout.corners = automatic.corners;
  std::array<std::vector<int>, polycube::num_cube_edges> fixed;
  fixed[0] = detour;
  std::string why;
  REQUIRE(polycube::complete_cuboid_layout(hm, 2, fixed, layout, &why));
  CHECK_THROWS_WITH_AS(param::compute_cuboid_surface_map(hm, layout), doctest::Contains("not bijective"), Error);

  polycube::SolidDecomposition d;
  d.mesh = cube;
  d.value.assign(cube.num_vertices(), 0.0);
  d.parent_face.resize(cube.num_faces());
  std::iota(d.parent_face.begin(), d.parent_face.end(), 0);
  d.pieces.resize(1);
  d.pieces[0].faces = d.parent_face;
  polycube::GpcConstruction gpc;
  gpc.surfaces.resize(1);
  polycube::CuboidSurface& s = gpc.surfaces[0];
  s.mesh = cube;
  s.layout = layout;
  s.surface_vertex.resize(cube.num_vertices());
  std::iota(s.surface_vertex.begin(), s.surface_vertex.end(), 0);
  s.surface_face = d.parent_face;
  polycube::split_poly_edge_chords(d, gpc);

  // One midpoint; the chord's two triangles split in two each, in both meshes alike.
  CHECK(s.mesh.num_vertices() == cube.num_vertices() + 1);
  CHECK(s.mesh.num_faces() == cube.num_faces() + 2);
  CHECK(s.mesh.positions.row(cube.num_vertices()).isApprox(0.5 * (cube.positions.row(p1) + cube.positions.row(p2))));
  CHECK(d.mesh.positions == s.mesh.positions);
  CHECK(d.mesh.triangles == s.mesh.triangles);
  CHECK(d.pieces[0].faces.size() == static_cast<std::size_t>(d.mesh.num_faces()));
  CHECK(d.parent_face.size() == static_cast<std::size_t>(d.mesh.num_faces()));
  CHECK(static_cast<int>(s.layout.face_region.size()) == s.mesh.num_faces());
  CHECK(s.surface_vertex.back() == cube.num_vertices());
  const auto split = mesh::HalfedgeMesh::build(s.mesh, "split cube");  // still closed and manifold
  auto area = [](const mesh::HalfedgeMesh& m) {
    const std::vector<double> a = mesh::face_areas(m);
    return std::accumulate(a.begin(), a.end(), 0.0);
  };
  CHECK(area(split) == doctest::Approx(area(hm)).epsilon(1e-14));
  const param::CuboidSurfaceMap map = param::compute_cuboid_surface_map(split, s.layout);
  CHECK(map.num_flipped == 0);

  // A layout of shortest paths has no chord: nothing changes.
  polycube::GpcConstruction plain = gpc;
  plain.surfaces[0].layout = automatic;
  plain.surfaces[0].mesh = cube;
  polycube::SolidDecomposition d2;
  d2.mesh = cube;
  polycube::split_poly_edge_chords(d2, plain);
  CHECK(plain.surfaces[0].mesh.num_vertices() == cube.num_vertices());
  CHECK(d2.mesh.triangles == cube.triangles);
}

TEST_CASE("disc chords: slivers a billion times thinner than the disc still map and cut bijectively") {
  // A 40 × 40 grid on the unit square whose columns 10, 20 and 30 sit 1e-9 right of their left
  // neighbours: the sliver strips' mean-value weights are about 1e9 against about 1 elsewhere,
  // as level-set splits leave them, and an iterative solve to a fixed tolerance then stalls or
  // stops with folds; the map must still be exact enough that no face turns over.
  const int k = 40;
  auto x_of = [&](int i) { return i % 10 == 0 && i > 0 && i < k ? double(i - 1) / k + 1e-9 : double(i) / k; };
  mesh::TriangleMesh m = paraboloid_disc(k, x_of);
  std::vector<int> region(m.num_faces());
  for (int f = 0; f < m.num_faces(); ++f) region[f] = f;
  const int c00 = 0, c10 = k, c11 = (k + 1) * (k + 1) - 1, c01 = k * (k + 1);
  // Left-side vertex 7 to right-side vertex 31: the chord crosses all three strips.
  const int l7 = 7 * (k + 1), r31 = 31 * (k + 1) + k;
  polycube::DiscChords dc;
  std::string why;
  REQUIRE_MESSAGE(polycube::cut_disc_chords(m, region, {c00, c10, c11, c01}, {{{l7, r31}}}, dc, &why), why);
  REQUIRE(dc.paths.size() == 1);
  CHECK(dc.paths[0].front() == l7);
  CHECK(dc.paths[0].back() == r31);
  const mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(m, "chords");
  const mesh::MeshReport report = mesh::analyze_mesh(hm);
  CHECK(report.num_boundary_loops == 1);
  CHECK(report.consistently_oriented);
}

// Around every cycle of the GPC graph (a spanning tree's missing interfaces) the transition
// maps compose to a pure translation: the cuboids' frames close up without a twist. Returns the
// number of cycles whose composed rotation is not the identity.
int twisted_cycles(const polycube::GpcDomain& domain) {
  const int n = static_cast<int>(domain.cuboids.size());
  std::vector<polycube::GpcTransition> to(n);  // root frame → cuboid frame
  std::vector<char> reached(n, 0), tree(domain.interfaces.size(), 0);
  std::vector<int> queue = {0};
  reached[0] = 1;
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const int a = queue[q];
    for (std::size_t k = 0; k < domain.interfaces.size(); ++k) {
      const auto& g = domain.interfaces[k];
      for (int side = 0; side < 2; ++side) {
        if (g.cuboid[side] != a || reached[g.cuboid[1 - side]]) continue;
        const polycube::GpcTransition t = side == 0 ? g.transition : g.transition.inverse();
        to[g.cuboid[1 - side]] = t.after(to[a]);
        reached[g.cuboid[1 - side]] = 1;
        tree[k] = 1;
        queue.push_back(g.cuboid[1 - side]);
      }
    }
  }
  int twisted = 0;
  for (std::size_t k = 0; k < domain.interfaces.size(); ++k) {
    if (tree[k]) continue;
    const auto& g = domain.interfaces[k];
    const polycube::GpcTransition around = to[g.cuboid[1]].inverse().after(g.transition.after(to[g.cuboid[0]]));
    twisted += !(around.axis == std::array<int, 3>{0, 1, 2} && around.sign == std::array<int, 3>{1, 1, 1});
  }
  return twisted;
}

TEST_CASE("gpc job: a two-hole solid is two T-shapes with Type-1 ill-points only, glued exactly") {
  const pipeline::GpcResult r = pipeline::run_gpc(test::two_hole_slab(3), "slab", without_untangling());
  const pipeline::GpcStats& s = r.stats;
  CHECK(s.genus == 2);
  CHECK(s.t_shapes == 2);
  CHECK(s.ill_points == 4);
  // 4 cuboids per T-shape; merging across cuts removes one cuboid and one interface per merge.
  pipeline::GpcOptions separate = without_untangling();
  separate.merge_cuboids = false;
  const pipeline::GpcResult u = pipeline::run_gpc(test::two_hole_slab(3), "slab", separate);
  CHECK(u.stats.cuboids == 8);
  CHECK(u.stats.ill_points == 4);
  CHECK(s.cuboids < 8);
  CHECK(u.stats.interfaces - s.interfaces == 8 - s.cuboids);
  for (const auto& p : r.construction.domain.ill_points) CHECK(p.type == 1);
  CHECK(s.flipped_triangles == 0);
  CHECK(s.interface_gap_rel <= 1e-12);
  CHECK(s.cut_discs_outside == 0);
  // Every interface glues by a rotation by multiples of π/2 (Eq. 3.4) whose inverse undoes it, and
  // each cuboid face is glued at most once.
  std::set<std::pair<int, int>> glued;
  for (const auto& g : r.construction.domain.interfaces) {
    const polycube::GpcTransition id = g.transition.after(g.transition.inverse());
    CHECK(id.axis == std::array<int, 3>{0, 1, 2});
    CHECK(id.sign == std::array<int, 3>{1, 1, 1});
    CHECK(id.translation.norm() < 1e-12);
    for (int k = 0; k < 2; ++k) CHECK(glued.insert({g.cuboid[k], g.face[k]}).second);
  }
  // Two independent cycles of the graph (genus 2).
  CHECK(s.interfaces - s.cuboids + 1 == 2);
}

TEST_CASE("Morse function: the multigrid and IC(0) solves agree, the same critical points") {
  const mesh::HalfedgeMesh t = outward(make_torus(48, 24));
  polycube::MorseFunctionOptions ic, amg;
  amg.multigrid_from = 0;
  const polycube::MorseFunction a = polycube::compute_morse_function(t, ic);
  const polycube::MorseFunction b = polycube::compute_morse_function(t, amg);
  REQUIRE(a.value.size() == b.value.size());
  double gap = 0.0;
  for (std::size_t v = 0; v < a.value.size(); ++v) gap = std::max(gap, std::abs(a.value[v] - b.value[v]));
  CHECK(gap < 1e-9);
  CHECK(a.num_saddles == 2);
  CHECK(b.num_saddles == a.num_saddles);
  CHECK(b.num_minima == 1);
  CHECK(b.num_maxima == 1);
}

TEST_CASE("Morse function: a multigrid tolerance below double precision's floor still ends, with the same function") {
  // A relative residual of 1e-30 is out of reach in double precision: the restarted chunks stop
  // once a chunk no longer halves the residual (without them CG would run 4m iterations).
  const mesh::HalfedgeMesh t = outward(make_torus(48, 24));
  polycube::MorseFunctionOptions ic, amg;
  amg.multigrid_from = 0;
  amg.tolerance = 1e-30;
  const polycube::MorseFunction a = polycube::compute_morse_function(t, ic);
  const polycube::MorseFunction b = polycube::compute_morse_function(t, amg);
  double gap = 0.0;
  for (std::size_t v = 0; v < a.value.size(); ++v) gap = std::max(gap, std::abs(a.value[v] - b.value[v]));
  CHECK(gap < 1e-9);
  CHECK(b.num_saddles == 2);
}

TEST_CASE("limbs: the three ends of a T-shaped solid become caps around one T-shape") {
  const mesh::HalfedgeMesh t = outward(make_t_solid(3));
  REQUIRE(mesh::analyze_mesh(t).genus == 0);
  polycube::MorseFunctionOptions limbs;
  limbs.limb_persistence = 0.25;
  const polycube::MorseFunction f = polycube::compute_morse_function(t, limbs);
  CHECK(f.limb_tips.size() == 1);      // the third end (source and sink are the other two)
  CHECK(f.num_maxima == 2);            // sink and tip, value 1
  CHECK(f.num_saddles == 1);           // χ = 2 = 1 − 1 + 2
  polycube::DecompositionOptions d;
  d.morse = limbs;
  const polycube::SolidDecomposition e = polycube::decompose_solid(t, 0, d);
  const auto [caps, tshapes] = count_pieces(e);
  CHECK(caps == 3);
  CHECK(tshapes == 1);
  // Every cap's cut is a cross-section of its bar (a rounded voxel square: perimeter about 4
  // voxels), not a loop running diagonally through the junction (a 45° loop: 2 + 2√2 = 4.83).
  const double voxel = (t.positions().col(0).maxCoeff() - t.positions().col(0).minCoeff()) / 7.0;
  for (const auto& loop : e.loops) {
    const bool cap = e.pieces[loop.piece[0]].kind == polycube::PieceKind::Cap ||
                     e.pieces[loop.piece[1]].kind == polycube::PieceKind::Cap;
    REQUIRE(cap);
    double length = 0.0;
    for (std::size_t i = 0; i < loop.vertices.size(); ++i)
      length += (e.mesh.positions.row(loop.vertices[i]) -
                 e.mesh.positions.row(loop.vertices[(i + 1) % loop.vertices.size()])).norm();
    CHECK(length > 3.4 * voxel);
    CHECK(length < 4.4 * voxel);
  }
  // By default the job cuts the three limbs off; with limbs off the solid stays one cuboid.
  const pipeline::GpcResult r = pipeline::run_gpc(make_t_solid(3), "T", without_untangling());
  CHECK(r.stats.limb_fallback == "");
  CHECK(r.stats.limb_caps == 3);
  CHECK(r.stats.t_shapes == 1);
  CHECK(r.stats.ill_points == 2);
  CHECK(r.stats.flipped_triangles == 0);
  CHECK(r.stats.interface_gap_rel <= 1e-12);
  CHECK(r.stats.cut_discs_outside == 0);
  pipeline::GpcOptions off = without_untangling();
  off.limb_persistence = 0.0;
  const pipeline::GpcResult blob = pipeline::run_gpc(make_t_solid(3), "T", off);
  CHECK(blob.stats.cuboids == 1);
}

TEST_CASE("gpc job: the retry with taller T-shape centres keeps the better hex mesh") {
  pipeline::GpcOptions o = small_grid();
  o.taller_centres_below = -1.0;
  const pipeline::GpcResult first = pipeline::run_gpc(make_t_solid(3), "T", o);
  CHECK(first.stats.taller_centres.empty());
  // Below a least scaled Jacobian of 1 every hex mesh is retried.
  o.taller_centres_below = 1.0;
  const pipeline::GpcResult retried = pipeline::run_gpc(make_t_solid(3), "T", o);
  CHECK(retried.stats.taller_centres.rfind("concave corners at 0.85 of the crotch's height: ", 0) == 0);
  CHECK(retried.stats.t_shapes == 1);
  CHECK(retried.stats.interface_gap_rel <= 1e-12);
  const bool kept = retried.stats.taller_centres.find("; kept it") != std::string::npos;
  CHECK(kept == (retried.stats.grid_min_scaled_jacobian != first.stats.grid_min_scaled_jacobian));
  CHECK(retried.stats.grid_inverted_hexes <= first.stats.grid_inverted_hexes);
  if (retried.stats.grid_inverted_hexes == first.stats.grid_inverted_hexes)
    CHECK(retried.stats.grid_min_scaled_jacobian >= first.stats.grid_min_scaled_jacobian);
  // By the share of inverted hexes alone (taller_centres_below off), with the hex mesh as
  // mesh2spline has it (surface held, no quality stage), which leaves the first construction
  // some inverted hexes: the retry runs iff more than that share of its hexes is inverted.
  o.taller_centres_below = -1.0;
  o.grid.face_sliding = param::GpcGridOptions::FaceSliding::Off;
  o.grid.min_quality_sweeps = 0;
  o.grid.padded_reference = param::GpcGridOptions::PaddedReference::MeanCell;
  const pipeline::GpcResult held = pipeline::run_gpc(make_t_solid(3), "T", o);
  CHECK(held.stats.taller_centres.empty());
  REQUIRE(held.stats.grid_inverted_hexes > 0);
  o.taller_centres_inverted_above = 0.5;  // far more than the few inverted hexes
  CHECK(pipeline::run_gpc(make_t_solid(3), "T", o).stats.taller_centres.empty());
  o.taller_centres_inverted_above = 1e-9;
  const pipeline::GpcResult by_share = pipeline::run_gpc(make_t_solid(3), "T", o);
  CHECK(by_share.stats.taller_centres.rfind("concave corners at 0.85 of the crotch's height: ", 0) == 0);
  CHECK(by_share.stats.grid_inverted_hexes <= held.stats.grid_inverted_hexes);
  for (const double bad : {0.0, 1.5}) {
    o.taller_centres_inverted_above = bad;
    CHECK_THROWS_WITH_AS(pipeline::run_gpc(make_t_solid(3), "T", o),
                         doctest::Contains("taller_centres_inverted_above must be in (0, 1]"), Error);
  }
  o.taller_centres_inverted_above = 1.0;
  o.taller_centres_below = 1.5;
  CHECK_THROWS_WITH_AS(pipeline::run_gpc(make_t_solid(3), "T", o), doctest::Contains("taller_centres_below must be in [-1, 1]"),
                       Error);
  o.taller_centres_below = 0.2;
  o.grid.wider_relax_below = -1.5;
  CHECK_THROWS_WITH_AS(pipeline::run_gpc(make_t_solid(3), "T", o), doctest::Contains("grid.wider_relax_below must be in [-1, 1]"),
                       Error);
}

TEST_CASE("gpc job: the eight's handles close without a twist") {
  // Each T-shape of the eight has both sides of one cut as its arms (a handle): its seams join
  // every corner of the cut to its own copy, so the merged ring closes without a twist.
  const mesh::TriangleMesh eight = io::read_mesh(std::string(VOLSPLINE_SHARED_DATA) + "/meshes/eight.off");
  const pipeline::GpcResult r = pipeline::run_gpc(eight, "eight", without_untangling());
  CHECK(r.stats.genus == 2);
  CHECK(r.stats.t_shapes == 2);
  CHECK(r.stats.cuboids == 5);
  CHECK(r.stats.ill_points == 4);
  CHECK(r.stats.interfaces - r.stats.cuboids + 1 == 2);
  CHECK(twisted_cycles(r.construction.domain) == 0);
}

TEST_CASE("Morse decomposition and cut flips: a plate with 2 x 2 holes, its 4-way junction split in two") {
  // The lattice's middle is a 4-way junction whose two saddles lie at one level: the piece
  // between the levels around them has 4 loops, split by a meridian into two T-shapes
  // (split_four_holed_piece). Its re-split cuts can run around a hole beside the pieces' other
  // loops; flips replace the long ones by shorter meridians, every piece still a T-shape.
  const mesh::HalfedgeMesh plate = outward(make_holed_plate(32));
  REQUIRE(mesh::analyze_mesh(plate).genus == 4);
  polycube::SolidDecomposition d = polycube::decompose_solid(plate, 4);
  auto check_pieces = [&] {
    REQUIRE(d.loops.size() == 9);
    REQUIRE(d.pieces.size() == 6);
    for (const polycube::SolidPiece& p : d.pieces) CHECK(p.kind == polycube::PieceKind::TShape);
    for (std::size_t p = 0; p < d.pieces.size(); ++p)
      for (const polycube::LoopSide& b : d.pieces[p].boundary)
        CHECK(d.loops[b.loop].piece[b.side] == static_cast<int>(p));
    for (const polycube::CutLoop& loop : d.loops)
      CHECK(polycube::check_loop_disc(d.mesh, loop.vertices).num_outside == 0);
    const mesh::MeshReport cut = mesh::analyze_mesh(mesh::HalfedgeMesh::build(d.mesh, "cut"));
    CHECK(cut.closed);
    CHECK(cut.genus == 4);
  };
  check_pieces();
  const polycube::CutFlips flips = polycube::flip_cuts(d);
  CHECK(flips.num_flipped >= 1);
  CHECK(flips.length_after < 0.8 * flips.length_before);
  check_pieces();
}

// A square ring one voxel thick (5 × 5 cells around a 3 × 3 hole) with a long bar on each side,
// in line: genus 1, the bars' tips the two ends of the graph diameter, no third limb.
namespace {
mesh::TriangleMesh make_ring_with_bars(int k) {
  return test::voxel_solid(21, 5, 1, k, [](int x, int y, int) {
    const bool ring = x >= 8 && x <= 12 && !(x >= 9 && x <= 11 && y >= 1 && y <= 3);
    return ring || (y == 2 && (x < 8 || x > 12));
  });
}
}  // namespace

TEST_CASE("pole caps: the two poles' pieces stay caps, so a torus is 2 caps and 2 T-shapes") {
  const mesh::HalfedgeMesh torus = outward(make_torus(32, 16));
  polycube::DecompositionOptions o;
  o.pole_caps = true;
  const polycube::SolidDecomposition d = polycube::decompose_solid(torus, 1, o);
  const auto [caps, tshapes] = count_pieces(d);
  CHECK(caps == 2);
  CHECK(tshapes == caps + 2 * 1 - 2);  // Euler characteristic count
}

TEST_CASE("gpc job: bars at the ends of the graph diameter become caps where the first map crowds them") {
  const mesh::TriangleMesh ring = make_ring_with_bars(1);
  pipeline::GpcOptions o = small_grid();
  o.pole_caps_below = 0.0;
  const pipeline::GpcResult first = pipeline::run_gpc(ring, "ring", o);
  CHECK(first.stats.genus == 1);
  CHECK(first.stats.caps == 0);
  CHECK(first.stats.pole_caps.empty());
  double first_least = 1.0;
  for (const auto& m : first.map.surface_maps) first_least = std::min(first_least, m.unrescued_least_density);
  CHECK(first_least < 1e-3);
  o.pole_caps_below = 1e-3;
  const pipeline::GpcResult r = pipeline::run_gpc(ring, "ring", o);
  CHECK(r.stats.caps == 2);
  CHECK(r.stats.t_shapes == 2);
  CHECK(r.stats.pole_caps.find("; kept it") != std::string::npos);
  double least = 1.0;
  for (const auto& m : r.map.surface_maps) least = std::min(least, m.unrescued_least_density);
  CHECK(least >= pipeline::kPoleCapsGain * first_least);
  CHECK(r.stats.interface_gap_rel <= 1e-12);
  CHECK(r.stats.cut_discs_outside == 0);
  o.pole_caps_below = 1.0;
  CHECK_THROWS_WITH_AS(pipeline::run_gpc(ring, "ring", o), doctest::Contains("pole_caps_below must be in [0, 1)"), Error);
}

TEST_CASE("gpc job: a cube's wireframe, symmetric about its diameter, is built with the poles off the axis") {
  const mesh::TriangleMesh frame = test::cube_frame(2);
  // At the diameter's ends (opposite corners, on a 3-fold axis) saddles meet at one level.
  CHECK_THROWS_AS(polycube::decompose_solid(outward(frame), 5), polycube::DecompositionError);
  const pipeline::GpcResult r = pipeline::run_gpc(frame, "frame", without_untangling());
  CHECK(r.stats.genus == 5);
  CHECK(r.stats.off_axis_poles.find("pole offset") != std::string::npos);
  CHECK(r.stats.caps == 0);
  CHECK(r.stats.t_shapes == 2 * 5 - 2);  // Euler count: #T = #caps + 2g − 2
  // Every cut bounds a disc inside the solid (its interface disc still crosses the coarse
  // surface: cut_disc_intersections is reported, not asserted).
  CHECK(r.stats.cut_discs_outside == 0);
  CHECK(r.stats.interface_gap_rel <= 1e-12);
}
