// SPDX-License-Identifier: MIT
#include "wasm/spline_preview.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <Eigen/LU>

namespace volspline::wasm {

namespace {

// Point of the unit cube with coordinate `axis` at `fixed` and the other two axes (cyclic order)
// at s and t.
Eigen::Vector3d unit_point(int axis, double fixed, double s, double t) {
  Eigen::Vector3d unit;
  unit(axis) = fixed;
  unit((axis + 1) % 3) = s;
  unit((axis + 2) % 3) = t;
  return unit;
}

// The domain parameter of a unit-cube point.
Eigen::Vector3d domain_point(const spline::TSpline& spline, const Eigen::Vector3d& unit) {
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  return lo + unit.cwiseProduct(hi - lo);
}

void push_point(std::vector<float>& out, const Eigen::VectorXd& p) {
  for (int d = 0; d < 3; ++d) out.push_back(static_cast<float>(p(d)));
}

// Two triangles per lattice cell of an m×m block starting at `base`; `flip` reverses them.
void push_lattice_triangles(std::vector<std::uint32_t>& out, std::uint32_t base, int m, bool flip) {
  for (int j = 0; j + 1 < m; ++j)
    for (int i = 0; i + 1 < m; ++i) {
      const std::uint32_t a = base + i + m * j, b = a + 1, c = a + m + 1, d = a + m;
      const std::uint32_t tri[6] = {a, b, c, a, c, d};
      for (int k = 0; k < 6; k += 3) {
        out.push_back(tri[k]);
        out.push_back(flip ? tri[k + 2] : tri[k + 1]);
        out.push_back(flip ? tri[k + 1] : tri[k + 2]);
      }
    }
}

}  // namespace

SplinePreview spline_preview(const spline::TSpline& spline, int samples, int lines) {
  assert(spline.dimension() == 3 && samples >= 2 && lines >= 2);
  SplinePreview out;
  const int m = samples;
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2;
    const double side = face % 2;
    const auto base = static_cast<std::uint32_t>(out.surface_xyz.size() / 3);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const Eigen::Vector3d uvw = unit_point(axis, side, double(i) / (m - 1), double(j) / (m - 1));
        push_point(out.surface_xyz, spline.evaluate(domain_point(spline, uvw)));
        push_point(out.surface_uvw, uvw);
      }
    push_lattice_triangles(out.surface_triangles, base, m, face % 2 == 0);
    const int steps = 4 * (m - 1);
    for (int dir = 0; dir < 2; ++dir)
      for (int l = 0; l < lines; ++l) {
        const double fixed = double(l) / (lines - 1);
        Eigen::VectorXd previous;
        Eigen::Vector3d previous_uvw;
        for (int q = 0; q <= steps; ++q) {
          const double moving = double(q) / steps;
          const Eigen::Vector3d uvw = dir == 0 ? unit_point(axis, side, fixed, moving) : unit_point(axis, side, moving, fixed);
          const Eigen::VectorXd p = spline.evaluate(domain_point(spline, uvw));
          if (q > 0) {
            push_point(out.line_xyz, previous);
            push_point(out.line_xyz, p);
            push_point(out.line_uvw, previous_uvw);
            push_point(out.line_uvw, uvw);
          }
          previous = p;
          previous_uvw = uvw;
        }
      }
  }
  const Eigen::MatrixXd& points = spline.points();
  out.control_xyz.reserve(points.rows() * 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (int d = 0; d < 3; ++d) out.control_xyz.push_back(static_cast<float>(points(i, d)));
  return out;
}

SplineCut spline_cut(const spline::TSpline& spline, int axis, double t, int samples) {
  assert(spline.dimension() == 3 && axis >= 0 && axis < 3 && t >= 0 && t <= 1 && samples >= 2);
  SplineCut out;
  const int m = samples;
  double value[3], jacobian[9];
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      spline.evaluate_with_jacobian(domain_point(spline, unit_point(axis, t, double(i) / (m - 1), double(j) / (m - 1))),
                                    spline::TSplineForm::SemiStandard, value, jacobian);
      for (int d = 0; d < 3; ++d) out.xyz.push_back(static_cast<float>(value[d]));
      const Eigen::Map<const Eigen::Matrix3d> J(jacobian);  // column a = ∂F/∂uvw_a
      const double scale = J.col(0).norm() * J.col(1).norm() * J.col(2).norm();
      // A collapsed direction (zero column) counts as degenerate, like a folded hex.
      const double q = scale > 0 ? std::clamp(J.determinant() / scale, -1.0, 1.0) : 0.0;
      out.scaled_jacobian.push_back(static_cast<float>(q));
      out.min_scaled_jacobian = std::min(out.min_scaled_jacobian, static_cast<float>(q));
    }
  push_lattice_triangles(out.triangles, 0, m, false);
  return out;
}

}  // namespace volspline::wasm
