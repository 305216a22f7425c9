// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

namespace volspline::spline {

/// Expands grid coordinates S = [s_1, ..., s_n] (strictly increasing, n >= 2) into the clamped
/// knot vector [s_1, s_1, s_1, s_1, s_2, ..., s_{n-1}, s_n, s_n, s_n, s_n] of §4.3.1 (3 boundary
/// knots added at each end), which carries n + 2 cubic basis functions all confined to
/// [s_1, s_n]. Throws volspline::Error if S is too short, not finite or not strictly increasing.
std::vector<double> boundary_restricted_knots(const std::vector<double>& grid);

/// Trivariate tensor-product cubic B-spline volume F: [u, v, w] -> R^D, D in 1..4
/// (D = 3 for geometry, 4 for geometry + density).
///
/// Knots: one clamped knot vector per axis (first 4 and last 4 knots equal, interior knots of
/// multiplicity <= 3, non-uniform allowed); axis a has n_a = knots(a).size() - 4 >= 4 basis
/// functions, basis function i of axis a has local knots knots(a)[i .. i+4].
/// Control points: n0·n1·n2 rows of a D-column matrix, row control_index(i0, i1, i2) =
/// i0 + n0·(i1 + n1·i2).
/// Domain: [knots(a).front(), knots(a).back()] per axis, closed at both ends (at the upper end
/// the last knot span is used, so F is continuous up to the boundary).
class BsplineVolume {
 public:
  /// Throws volspline::Error (naming the axis/knot) if a knot vector is not finite,
  /// decreasing, not clamped, has fewer than 8 knots or an interior knot of multiplicity > 3,
  /// or if control_points is not (n0·n1·n2)×D with D in 1..4 and finite entries.
  BsplineVolume(std::array<std::vector<double>, 3> knots, Eigen::MatrixXd control_points);

  /// Number D of components of F.
  int dimension() const { return static_cast<int>(control_points_.cols()); }
  /// Number of basis functions n_a along axis a (0..2).
  int num_control(int axis) const { return num_control_[axis]; }
  /// Clamped knot vector of axis a.
  const std::vector<double>& knots(int axis) const { return knots_[axis]; }
  /// (n0·n1·n2)×D control points.
  const Eigen::MatrixXd& control_points() const { return control_points_; }
  /// Row of control point (i0, i1, i2) in control_points().
  int control_index(int i0, int i1, int i2) const {
    return i0 + num_control_[0] * (i1 + num_control_[1] * i2);
  }
  /// Lower domain corner (u, v, w).
  Eigen::Vector3d domain_min() const;
  /// Upper domain corner (u, v, w).
  Eigen::Vector3d domain_max() const;

  /// Greville abscissa (r1 + r2 + r3)/3 of basis function i along axis a; placing control points
  /// there makes F reproduce linear functions.
  double greville_abscissa(int axis, int i) const;

  /// Knot span s of axis a containing t, by binary search: knots[s] <= t < knots[s+1] with
  /// 3 <= s <= n_a - 1; t = domain end gives s = n_a - 1. Precondition: t inside the domain.
  int find_span(int axis, double t) const;

  /// F(uvw), D values. Throws volspline::Error if uvw is outside the domain or not finite.
  Eigen::VectorXd evaluate(const Eigen::Vector3d& uvw) const;
  /// F(uvw) written to value[0..D); no allocation. Throws like evaluate.
  void evaluate_to(const Eigen::Vector3d& uvw, double* value) const;
  /// Partial derivative ∂^(o0+o1+o2) F / ∂u^o0 ∂v^o1 ∂w^o2 at uvw, D values; each order 0..3.
  /// Throws like evaluate.
  Eigen::VectorXd derivative(const Eigen::Vector3d& uvw, const std::array<int, 3>& order) const;
  /// F(uvw) and the D×3 Jacobian [∂F/∂u ∂F/∂v ∂F/∂w] (3×3 for geometry); jacobian is written
  /// column-major (jacobian[d + D·a] = ∂F_d/∂uvw_a). No allocation. Throws like evaluate.
  void evaluate_with_jacobian(const Eigen::Vector3d& uvw, double* value, double* jacobian) const;
  /// D×3 Jacobian at uvw. Throws like evaluate.
  Eigen::MatrixXd jacobian(const Eigen::Vector3d& uvw) const;
  /// F at each row of uvw (m×3); returns m×D. Throws like evaluate, naming the row.
  Eigen::MatrixXd evaluate_batch(const Eigen::MatrixX3d& uvw) const;

 private:
  template <int kOrder>
  void basis_along(int axis, double t, int* first, double (*values)[4]) const;
  void check_parameter(const Eigen::Vector3d& uvw) const;

  std::array<std::vector<double>, 3> knots_;
  std::array<int, 3> num_control_{};
  Eigen::MatrixXd control_points_;
};

}  // namespace volspline::spline
