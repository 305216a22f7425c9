// SPDX-License-Identifier: MIT
#include "core/pipeline/gpc_spline_measures.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Cholesky>
#include <string>

#include "core/common/error.h"
#include "core/mesh/hex_quality.h"
#include "core/param/surface_distance.h"
#include "core/pipeline/mesh2spline_measures.h"

namespace volspline::pipeline {

namespace {

void check_options(const GpcSplineMeasureOptions& o) {
  auto fail = [](const std::string& what) { throw Error("gpc spline measures: " + what); };
  if (o.surface_samples < 8 || o.surface_samples > 512) fail("`surface_samples` must be in [8, 512]");
  if (o.jacobian_gauss_points < 1 || o.jacobian_gauss_points > 8) fail("`jacobian_gauss_points` must be in [1, 8]");
  if (o.lattice < 4 || o.lattice > 256) fail("`lattice` must be in [4, 256]");
  if (o.interface_samples < 2 || o.interface_samples > 512) fail("`interface_samples` must be in [2, 512]");
  if (o.semi_standard_samples < 1) fail("`semi_standard_samples` must be ≥ 1");
}

Eigen::Vector3d box_of(const polycube::GpcCuboid& c) { return {c.size[0], c.size[1], c.size[2]}; }

// Scaled Jacobians at a tensor lattice of cuboid c (coordinates inside its box): count of
// points ≤ 0 and the least value.
void lattice_jacobians(const spline::GpcSpline& spline, int c, const std::array<std::vector<double>, 3>& coords,
                       long& negative, double& min_q) {
  spline.patch(c).evaluate_lattice_with_jacobian(coords, [&](int, int, int, const double*, const double* jacobian) {
    const double q = mesh::scaled_jacobian(Eigen::Map<const Eigen::Matrix3d>(jacobian));
    if (q <= 0.0) ++negative;
    min_q = std::min(min_q, q);
  });
}

// The rotation part of a transition as a matrix: T(x) = R x + t.
Eigen::Matrix3d rotation_of(const polycube::GpcTransition& t) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) r(t.axis[i], i) = t.sign[i];
  return r;
}

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double na = a.norm(), nb = b.norm();
  if (!(na > 0.0) || !(nb > 0.0)) return 180.0;
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

}  // namespace

double gpc_surface_point_distance(const spline::GpcSpline& spline, const GpcSurfacePoint& p) {
  const polycube::GpcCuboid& cu = spline.domain().cuboids[p.cuboid];
  double value[3], jac0[9];
  spline.evaluate_with_jacobian(p.cuboid, p.uvw, value, jac0);
  const Eigen::Vector3d r0 = Eigen::Map<Eigen::Vector3d>(value) - p.xyz;
  double least = r0.norm();
  for (int f = 0; f < 6; ++f) {
    const double at = f % 2 ? cu.size[f / 2] : 0.0;
    if (cu.face_interface[f] >= 0 || std::abs(p.uvw(f / 2) - at) > 1e-12 * (1.0 + cu.size[f / 2])) continue;
    const int b = (f / 2 + 1) % 3, e = (f / 2 + 2) % 3;
    Eigen::Vector3d uvw = p.uvw, r = r0;
    double best = r0.norm(), jac[9];
    std::copy(jac0, jac0 + 9, jac);
    for (int step = 0; step < 8 && best > 0.0; ++step) {
      const Eigen::Map<Eigen::Matrix3d> j(jac);
      Eigen::Matrix<double, 3, 2> t;
      t << j.col(b), j.col(e);
      const Eigen::Matrix2d normal = t.transpose() * t;
      if (!(normal.determinant() > 0.0)) break;
      const Eigen::Vector2d delta = -normal.ldlt().solve(t.transpose() * r);
      Eigen::Vector3d next = uvw;
      next(b) = std::clamp(next(b) + delta(0), 0.0, cu.size[b]);
      next(e) = std::clamp(next(e) + delta(1), 0.0, cu.size[e]);
      spline.evaluate_with_jacobian(p.cuboid, next, value, jac);
      const Eigen::Vector3d rn = Eigen::Map<Eigen::Vector3d>(value) - p.xyz;
      if (!(rn.norm() < best)) break;
      best = rn.norm();
      r = rn;
      uvw = next;
    }
    least = std::min(least, best);
  }
  return least;
}

GpcSplineMeasures measure_gpc_spline(const spline::GpcSpline& spline, const mesh::TriangleMesh& mesh,
                                     const std::vector<GpcSurfacePoint>& surface_points, double diagonal,
                                     const GpcSplineMeasureOptions& options) {
  check_options(options);
  if (spline.dimension() != 3) throw Error("gpc spline measures: the spline must have 3 components");
  if (!(diagonal > 0.0)) throw Error("gpc spline measures: the diagonal must be positive");
  const polycube::GpcDomain& domain = spline.domain();
  GpcSplineMeasures m;

  // Two-sided boundary distance (DESIGN.md hausdorff_rel, rms_geo_rel).
  const param::SurfaceDistance distance(mesh);
  double max_d = 0.0, sum2 = 0.0;
  long count = 0;
  const int k = options.surface_samples;
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    const Eigen::Vector3d size = box_of(domain.cuboids[c]);
    for (int f = 0; f < 6; ++f) {
      if (domain.cuboids[c].face_interface[f] >= 0) continue;
      const int a = f / 2, b = (a + 1) % 3, e = (a + 2) % 3;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
          Eigen::Vector3d uvw;
          uvw(a) = f % 2 ? size(a) : 0.0;
          uvw(b) = size(b) * (i + 0.5) / k;
          uvw(e) = size(e) * (j + 0.5) / k;
          const double d = distance.distance(spline.evaluate(c, uvw));
          max_d = std::max(max_d, d);
          sum2 += d * d;
          ++count;
        }
    }
  }
  for (const GpcSurfacePoint& p : surface_points) {
    const double d = gpc_surface_point_distance(spline, p);
    max_d = std::max(max_d, d);
    sum2 += d * d;
    ++count;
  }
  m.hausdorff_rel = max_d / diagonal;
  m.rms_geo_rel = count ? std::sqrt(sum2 / count) / diagonal : 0.0;

  // Scaled Jacobian at the Gauss points of every knot cell and at the lattice cell centres.
  const std::vector<double> nodes = gauss_legendre_nodes(options.jacobian_gauss_points);
  long gauss_negative = 0, lattice_negative = 0;
  double gauss_min = 1.0, lattice_min = 1.0;
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    const Eigen::Vector3d size = box_of(domain.cuboids[c]);
    std::array<std::vector<double>, 3> gauss, lattice;
    long gauss_count = 1;
    for (int a = 0; a < 3; ++a) {
      const int n = spline.intervals(c)[a];
      for (int i = 0; i < n; ++i)
        for (double t : nodes) gauss[a].push_back(size(a) * (i + t) / n);
      for (int i = 0; i < options.lattice; ++i) lattice[a].push_back(size(a) * (i + 0.5) / options.lattice);
      gauss_count *= static_cast<long>(gauss[a].size());
    }
    lattice_jacobians(spline, c, gauss, gauss_negative, gauss_min);
    lattice_jacobians(spline, c, lattice, lattice_negative, lattice_min);
    m.jacobian_samples += gauss_count;
    m.lattice_samples += static_cast<long>(options.lattice) * options.lattice * options.lattice;
  }
  m.min_scaled_jacobian = gauss_min;
  m.negative_jacobian_fraction = m.jacobian_samples ? double(gauss_negative) / double(m.jacobian_samples) : 0.0;
  m.lattice_negative_fraction = m.lattice_samples ? double(lattice_negative) / double(m.lattice_samples) : 0.0;

  // Σ B_i − 1 at random parameters (Eq. 4.3 with w_i = 1), cuboids picked uniformly.
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> pick(0, spline.num_cuboids() - 1);
  for (int s = 0; s < options.semi_standard_samples; ++s) {
    const int c = pick(rng);
    Eigen::Vector3d uvw;
    for (int a = 0; a < 3; ++a) uvw(a) = unit(rng) * domain.cuboids[c].size[a];
    m.semi_standard_max_error = std::max(m.semi_standard_max_error, std::abs(spline.weight_sum(c, uvw) - 1.0));
  }

  // Both sides of every glued face (Eq. 3.4 maps side 0's point to side 1's).
  const int q = options.interface_samples;
  double gap = 0.0, jump = 0.0;
  double jac0[9], jac1[9], f0[3], f1[3];
  for (std::size_t g = 0; g < domain.interfaces.size(); ++g) {
    const polycube::GpcInterface& face = domain.interfaces[g];
    const int c0 = face.cuboid[0], c1 = face.cuboid[1];
    const Eigen::Vector3d size = box_of(domain.cuboids[c0]);
    const int a = face.face[0] / 2, b = (a + 1) % 3, e = (a + 2) % 3;
    const bool continued = spline.interface_join(static_cast<int>(g)) == spline::GpcFaceJoin::Continued;
    const Eigen::Matrix3d r = rotation_of(face.transition);
    for (int j = 0; j < q; ++j)
      for (int i = 0; i < q; ++i) {
        Eigen::Vector3d uvw;
        uvw(a) = face.face[0] % 2 ? size(a) : 0.0;
        uvw(b) = size(b) * i / (q - 1);
        uvw(e) = size(e) * j / (q - 1);
        const Eigen::Vector3d other = face.transition.apply(uvw);
        spline.evaluate_with_jacobian(c0, uvw, f0, jac0);
        spline.evaluate_with_jacobian(c1, other, f1, jac1);
        gap = std::max(gap, (Eigen::Map<Eigen::Vector3d>(f0) - Eigen::Map<Eigen::Vector3d>(f1)).norm());
        if (!continued) continue;
        // F_0(x) = F_1(R x + t): side 0's derivative along axis a is side 1's along R e_a.
        const Eigen::Vector3d d0 = Eigen::Map<Eigen::Matrix3d>(jac0).col(a);
        const Eigen::Vector3d d1 = Eigen::Map<Eigen::Matrix3d>(jac1) * r.col(a);
        jump = std::max(jump, angle_deg(d0, d1));
      }
  }
  m.interface_gap_rel = gap / diagonal;
  m.interface_normal_jump_deg = jump;
  return m;
}

}  // namespace volspline::pipeline
