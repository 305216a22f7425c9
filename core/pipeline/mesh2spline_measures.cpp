// SPDX-License-Identifier: MIT
#include "core/pipeline/mesh2spline_measures.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "core/common/error.h"
#include "core/mesh/hex_quality.h"
#include "core/polycube/cube_faces.h"
#include "core/param/cuboid_surface_map.h"
#include "core/param/surface_distance.h"

namespace volspline::pipeline {

namespace {

using spline::TSplineForm;

void check_options(const Mesh2SplineMeasureOptions& o) {
  auto fail = [](const std::string& what) { throw Error("mesh2spline measures: " + what); };
  if (o.surface_samples < 8 || o.surface_samples > 512) fail("surface samples must be in [8, 512]");
  if (o.jacobian_gauss_points < 1 || o.jacobian_gauss_points > 8) fail("the Jacobian Gauss points must be in [1, 8]");
  if (o.semi_standard_samples < 1) fail("semi-standard samples must be ≥ 1");
}

Eigen::Vector3d evaluate(const spline::TSpline& spline, const Eigen::Vector3d& uvw) {
  Eigen::Vector3d f;
  spline.evaluate_to(uvw, TSplineForm::SemiStandard, f.data());
  return f;
}

// F on an m×m lattice of each cube face, triangulated (two triangles per lattice square).
mesh::TriangleMesh boundary_lattice(const spline::TSpline& spline, int m) {
  mesh::TriangleMesh boundary;
  boundary.positions.resize(6 * m * m, 3);
  boundary.triangles.resize(6 * 2 * (m - 1) * (m - 1), 3);
  int t = 0;
  for (int face = 0; face < 6; ++face) {
    const int base = face * m * m;
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        boundary.positions.row(base + i + m * j) =
            evaluate(spline, polycube::cube_face_point(face, double(i) / (m - 1), double(j) / (m - 1))).transpose();
    for (int j = 0; j + 1 < m; ++j)
      for (int i = 0; i + 1 < m; ++i) {
        const int a = base + i + m * j;
        boundary.triangles.row(t++) << a, a + 1, a + m + 1;
        boundary.triangles.row(t++) << a, a + m + 1, a + m;
      }
  }
  return boundary;
}

}  // namespace

double surface_projection_distance(const spline::TSpline& spline, Eigen::Vector3d uvw, const Eigen::Vector3d& x) {
  int axis = 0;
  for (int a = 0; a < 3; ++a)
    if (uvw(a) <= 0.0 || uvw(a) >= 1.0) axis = a;
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  // F and its Jacobian come from one evaluation; the accepted point's Jacobian is the next
  // step's, so each step costs one evaluation.
  Eigen::Vector3d f;
  Eigen::Matrix3d jac;
  spline.evaluate_with_jacobian(uvw, TSplineForm::SemiStandard, f.data(), jac.data());
  double best = (f - x).norm();
  for (int iteration = 0; iteration < 6; ++iteration) {
    Eigen::Matrix<double, 3, 2> t;
    t << jac.col(b), jac.col(c);
    const Eigen::Matrix2d normal = t.transpose() * t;
    if (!(std::abs(normal.determinant()) > 1e-300)) break;
    const Eigen::Vector2d step = normal.ldlt().solve(t.transpose() * (x - f));
    Eigen::Vector3d next = uvw;
    next(b) = std::clamp(next(b) + step(0), 0.0, 1.0);
    next(c) = std::clamp(next(c) + step(1), 0.0, 1.0);
    Eigen::Vector3d fn;
    Eigen::Matrix3d jn;
    spline.evaluate_with_jacobian(next, TSplineForm::SemiStandard, fn.data(), jn.data());
    if ((fn - x).norm() >= best) break;
    uvw = next;
    f = fn;
    jac = jn;
    best = (f - x).norm();
  }
  return best;
}

std::vector<double> gauss_legendre_nodes(int n) {
  // Roots of P_n by Newton from the Chebyshev guesses, mapped to [0, 1].
  std::vector<double> nodes(n);
  for (int i = 0; i < n; ++i) {
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5));
    for (int it = 0; it < 50; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1, p1 = p2;
      }
      const double derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    nodes[n - 1 - i] = 0.5 * (1.0 + x);
  }
  return nodes;
}

Mesh2SplineMeasureResult measure_mesh2spline(const spline::TSpline& spline, const mesh::HalfedgeMesh& mesh,
                                        const mesh::Positions& vertex_uvw,
                                        const spline::RefinementGrid& refinement, double diagonal,
                                        const Mesh2SplineMeasureOptions& options) {
  check_options(options);
  Mesh2SplineMeasureResult measures;
  const int m = options.surface_samples;
  const mesh::TriangleMesh boundary = boundary_lattice(spline, m);
  const param::SurfaceDistance to_mesh(mesh.to_triangle_mesh());
  const param::SurfaceDistance to_spline(boundary);
  double max_d = 0.0, sum2 = 0.0;
  int count = 0;
  for (int i = 0; i < boundary.num_vertices(); ++i) {
    const double d = to_mesh.distance(boundary.positions.row(i).transpose());
    max_d = std::max(max_d, d);
    sum2 += d * d;
    ++count;
  }
  // The uniform lattice is coarse where the surface map is compressed (ears, tips): there the
  // spline surface is also sampled on the boundary faces of every refined leaf cell. These
  // points only enter the maximum, so a point with a triangle within the current maximum needs
  // no exact distance.
  for (int leaf : refinement.leaves()) {
    if (refinement.cell_level(leaf) == 0) continue;
    const Eigen::Vector3d lo_cell = refinement.cell_min(leaf), hi_cell = refinement.cell_max(leaf);
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        if (side == 0 ? lo_cell(a) > 0.0 : hi_cell(a) < 1.0) continue;
        for (int j = 0; j <= 2; ++j)
          for (int i = 0; i <= 2; ++i) {
            Eigen::Vector3d p = lo_cell;
            p(a) = side;
            p((a + 1) % 3) += (hi_cell((a + 1) % 3) - lo_cell((a + 1) % 3)) * i / 2.0;
            p((a + 2) % 3) += (hi_cell((a + 2) % 3) - lo_cell((a + 2) % 3)) * j / 2.0;
            const Eigen::Vector3d f = evaluate(spline, p);
            if (!to_mesh.within(f, max_d)) max_d = std::max(max_d, to_mesh.distance(f));
          }
      }
  }
  // Mesh → spline: the distance to the lattice triangles, or, where less, to the spline
  // surface point found by Gauss–Newton from the vertex's own surface parameter (the lattice
  // triangles cut corners where the map is compressed; the projection is on the surface). The
  // projection bounds the lattice search.
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.vertex_halfedge(v) == mesh::no_id) continue;
    const Eigen::Vector3d x = mesh.vertex_position(v);
    const double projected = surface_projection_distance(spline, vertex_uvw.row(v).transpose(), x);
    const double d = to_spline.distance_below(x, projected);
    max_d = std::max(max_d, d);
    sum2 += d * d;
    ++count;
  }
  measures.hausdorff_rel = max_d / diagonal;
  measures.rms_geo_rel = std::sqrt(sum2 / count) / diagonal;

  // The Gauss points of every knot interval per axis; one tensor-product pass per knot-line cell
  // (the count and the minimum do not depend on the visiting order).
  const std::vector<double> nodes = gauss_legendre_nodes(options.jacobian_gauss_points);
  std::array<std::vector<double>, 3> gauss;
  for (int a = 0; a < 3; ++a) {
    const std::vector<double>& b = spline.knot_lines(a);
    for (size_t k = 0; k + 1 < b.size(); ++k)
      for (double t : nodes) gauss[a].push_back(b[k] + t * (b[k + 1] - b[k]));
  }
  long negative = 0;
  double min_q = 1.0;
  spline.evaluate_lattice_with_jacobian(gauss, [&](int, int, int, const double*, const double* jacobian) {
    const double q = mesh::scaled_jacobian(Eigen::Map<const Eigen::Matrix3d>(jacobian));
    if (q <= 0.0) ++negative;
    min_q = std::min(min_q, q);
  });
  measures.jacobian_samples = long(gauss[0].size()) * long(gauss[1].size()) * long(gauss[2].size());
  measures.min_scaled_jacobian = min_q;
  measures.negative_jacobian_fraction = double(negative) / double(measures.jacobian_samples);

  // The same random parameters as drawn, visited in Morton order: neighbours share their cell's
  // function list in cache, and the maximum does not depend on the order.
  std::mt19937_64 rng(options.seed);
  const int num_random = options.semi_standard_samples;
  std::vector<Eigen::Vector3d> random_uvw(num_random);
  std::vector<std::pair<std::uint32_t, int>> morton(num_random);
  for (int s = 0; s < num_random; ++s) {
    for (int a = 0; a < 3; ++a) random_uvw[s](a) = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    std::uint32_t code = 0;
    for (int bit = 9; bit >= 0; --bit)
      for (int a = 2; a >= 0; --a)
        code = (code << 1) | ((static_cast<std::uint32_t>(random_uvw[s](a) * 1024.0) >> bit) & 1u);
    morton[s] = {code, s};
  }
  std::sort(morton.begin(), morton.end());
  double worst = 0.0;
  for (const auto& [code, s] : morton) worst = std::max(worst, std::abs(spline.weight_sum(random_uvw[s]) - 1.0));
  measures.semi_standard_max_error = worst;
  return measures;
}

}  // namespace volspline::pipeline
