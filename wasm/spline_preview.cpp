// SPDX-License-Identifier: MIT
#include "wasm/spline_preview.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <Eigen/LU>

#include "core/polycube/cube_faces.h"
#include "core/spline/boundary_tessellation.h"

namespace volspline::wasm {

namespace {

// The domain parameter of a unit-cube point.
Eigen::Vector3d domain_point(const spline::TSpline& spline, const Eigen::Vector3d& unit) {
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  return lo + unit.cwiseProduct(hi - lo);
}

}  // namespace

SplinePreview spline_preview(const spline::TSpline& spline, int samples, int lines) {
  assert(spline.dimension() == 3 && samples >= 2 && lines >= 2);
  SplinePreview out;
  spline::BoundaryTessellation boundary = spline::tessellate_boundary(spline, samples, lines);
  out.surface_xyz = std::move(boundary.surface_xyz);
  out.surface_uvw = std::move(boundary.surface_uvw);
  out.surface_triangles = std::move(boundary.surface_triangles);
  out.line_xyz = std::move(boundary.line_xyz);
  out.line_uvw = std::move(boundary.line_uvw);
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
      // The cut is the plane uvw[axis] = t: the low face of that axis moved to t.
      Eigen::Vector3d unit = polycube::cube_face_point(2 * axis, double(i) / (m - 1), double(j) / (m - 1));
      unit(axis) = t;
      const Eigen::Vector3d uvw = domain_point(spline, unit);
      spline.evaluate_with_jacobian(uvw, spline::TSplineForm::SemiStandard, value, jacobian);
      for (int d = 0; d < 3; ++d) out.uvw.push_back(static_cast<float>(uvw[d]));
      for (int d = 0; d < 3; ++d) out.xyz.push_back(static_cast<float>(value[d]));
      const Eigen::Map<const Eigen::Matrix3d> J(jacobian);  // column a = ∂F/∂uvw_a
      const double scale = J.col(0).norm() * J.col(1).norm() * J.col(2).norm();
      // A collapsed direction (zero column) counts as degenerate, like a folded hex.
      const double q = scale > 0 ? std::clamp(J.determinant() / scale, -1.0, 1.0) : 0.0;
      out.scaled_jacobian.push_back(static_cast<float>(q));
      out.min_scaled_jacobian = std::min(out.min_scaled_jacobian, static_cast<float>(q));
    }
  spline::append_lattice_triangles(out.triangles, 0, m, false);
  return out;
}

}  // namespace volspline::wasm
