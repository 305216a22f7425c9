// SPDX-License-Identifier: MIT
#include "core/spline/bspline_volume.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/spline/bspline_basis.h"

namespace volspline::spline {

namespace {

using detail::kAxisName;

void check_knot_vector(const std::vector<double>& knots, int axis) {
  const std::string where = std::string("B-spline volume: knot vector ") + kAxisName[axis];
  if (knots.size() < 8) {
    throw Error(where + " has " + std::to_string(knots.size()) +
                " knots, need at least 8 (4 basis functions)");
  }
  for (size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i])) throw Error(where + ": knot " + std::to_string(i) + " is not finite");
    if (i > 0 && knots[i] < knots[i - 1]) {
      throw Error(where + ": knot " + std::to_string(i) + " is smaller than the knot before it");
    }
  }
  const size_t n = knots.size();
  if (knots[0] != knots[3] || knots[n - 4] != knots[n - 1]) {
    throw Error(where + " is not clamped (first 4 and last 4 knots must be equal)");
  }
  if (knots[3] == knots[4] || knots[n - 5] == knots[n - 4]) {
    throw Error(where + " has an end knot of multiplicity > 4");
  }
  for (size_t i = 4; i + 4 < n; ++i) {
    size_t m = 1;
    while (i + m + 4 < n && knots[i + m] == knots[i]) ++m;
    if (m > 3) throw Error(where + ": interior knot " + std::to_string(i) + " has multiplicity > 3");
    i += m - 1;
  }
}

}  // namespace

std::vector<double> boundary_restricted_knots(const std::vector<double>& grid) {
  if (grid.size() < 2) throw Error("boundary knots: need at least 2 grid coordinates");
  for (size_t i = 0; i < grid.size(); ++i) {
    if (!std::isfinite(grid[i])) throw Error("boundary knots: grid coordinate " + std::to_string(i) + " is not finite");
    if (i > 0 && !(grid[i] > grid[i - 1])) {
      throw Error("boundary knots: grid coordinate " + std::to_string(i) + " is not larger than the one before");
    }
  }
  // §4.3.1: replicate each end knot 3 more times so every blending function stays in the domain.
  std::vector<double> knots(3, grid.front());
  knots.insert(knots.end(), grid.begin(), grid.end());
  knots.insert(knots.end(), 3, grid.back());
  return knots;
}

BsplineVolume::BsplineVolume(std::array<std::vector<double>, 3> knots, Eigen::MatrixXd control_points)
    : knots_(std::move(knots)), control_points_(std::move(control_points)) {
  for (int a = 0; a < 3; ++a) {
    check_knot_vector(knots_[a], a);
    num_control_[a] = static_cast<int>(knots_[a].size()) - 4;
  }
  const long expected = long(num_control_[0]) * num_control_[1] * num_control_[2];
  if (control_points_.rows() != expected) {
    throw Error("B-spline volume: " + std::to_string(control_points_.rows()) +
                " control points given, knot vectors need " + std::to_string(expected));
  }
  if (control_points_.cols() < 1 || control_points_.cols() > 4) {
    throw Error("B-spline volume: control point dimension " + std::to_string(control_points_.cols()) +
                " is not in 1..4");
  }
  for (Eigen::Index i = 0; i < control_points_.rows(); ++i) {
    if (!control_points_.row(i).allFinite()) {
      throw Error("B-spline volume: control point " + std::to_string(i) + " is not finite");
    }
  }
}

Eigen::Vector3d BsplineVolume::domain_min() const {
  return {knots_[0].front(), knots_[1].front(), knots_[2].front()};
}

Eigen::Vector3d BsplineVolume::domain_max() const {
  return {knots_[0].back(), knots_[1].back(), knots_[2].back()};
}

double BsplineVolume::greville_abscissa(int axis, int i) const {
  const std::vector<double>& k = knots_[axis];
  return (k[i + 1] + k[i + 2] + k[i + 3]) / 3.0;
}

int BsplineVolume::find_span(int axis, double t) const {
  const std::vector<double>& k = knots_[axis];
  const int n = num_control_[axis];
  // Spans live in knots[3 .. n]; upper_bound gives the first knot > t.
  const auto it = std::upper_bound(k.begin() + 4, k.begin() + n, t);
  return static_cast<int>(it - k.begin()) - 1;
}

void BsplineVolume::check_parameter(const Eigen::Vector3d& uvw) const {
  for (int a = 0; a < 3; ++a) {
    if (!(uvw[a] >= knots_[a].front() && uvw[a] <= knots_[a].back())) {
      throw Error("B-spline volume: parameter " + std::string(kAxisName[a]) + " = " +
                  std::to_string(uvw[a]) + " is outside the domain [" +
                  std::to_string(knots_[a].front()) + ", " + std::to_string(knots_[a].back()) + "]");
    }
  }
}

// values[m][k]: derivative of order k (0..kOrder) of basis function first+m at t.
template <int kOrder>
void BsplineVolume::basis_along(int axis, double t, int* first, double (*values)[4]) const {
  const int s = find_span(axis, t);
  *first = s - 3;
  const double* k = knots_[axis].data();
  for (int m = 0; m < 4; ++m) {
    const int i = s - 3 + m;
    const LocalKnots r = {k[i], k[i + 1], k[i + 2], k[i + 3], k[i + 4]};
    // Function i covers span s as its piece j = s - i = 3 - m.
    if (kOrder == 0) {
      values[m][0] = cubic_basis_piece_value(r, 3 - m, t);
    } else {
      const BasisDerivatives b = cubic_basis_piece_derivatives(r, 3 - m, t);
      values[m][0] = b.value;
      values[m][1] = b.d1;
      values[m][2] = b.d2;
      values[m][3] = b.d3;
    }
  }
}

void BsplineVolume::evaluate_to(const Eigen::Vector3d& uvw, double* value) const {
  check_parameter(uvw);
  int first[3];
  double basis[3][4][4];
  for (int a = 0; a < 3; ++a) basis_along<0>(a, uvw[a], &first[a], basis[a]);
  const int dim = dimension();
  for (int d = 0; d < dim; ++d) value[d] = 0.0;
  for (int m2 = 0; m2 < 4; ++m2) {
    for (int m1 = 0; m1 < 4; ++m1) {
      const double b12 = basis[1][m1][0] * basis[2][m2][0];
      const int row0 = control_index(first[0], first[1] + m1, first[2] + m2);
      for (int m0 = 0; m0 < 4; ++m0) {
        const double b = basis[0][m0][0] * b12;
        for (int d = 0; d < dim; ++d) value[d] += b * control_points_(row0 + m0, d);
      }
    }
  }
}

Eigen::VectorXd BsplineVolume::evaluate(const Eigen::Vector3d& uvw) const {
  Eigen::VectorXd value(dimension());
  evaluate_to(uvw, value.data());
  return value;
}

Eigen::VectorXd BsplineVolume::derivative(const Eigen::Vector3d& uvw,
                                          const std::array<int, 3>& order) const {
  check_parameter(uvw);
  int first[3];
  double basis[3][4][4];
  for (int a = 0; a < 3; ++a) {
    assert(order[a] >= 0 && order[a] <= 3);
    basis_along<3>(a, uvw[a], &first[a], basis[a]);
  }
  Eigen::VectorXd value = Eigen::VectorXd::Zero(dimension());
  for (int m2 = 0; m2 < 4; ++m2) {
    for (int m1 = 0; m1 < 4; ++m1) {
      for (int m0 = 0; m0 < 4; ++m0) {
        const double b = basis[0][m0][order[0]] * basis[1][m1][order[1]] * basis[2][m2][order[2]];
        value += b * control_points_.row(control_index(first[0] + m0, first[1] + m1, first[2] + m2)).transpose();
      }
    }
  }
  return value;
}

void BsplineVolume::evaluate_with_jacobian(const Eigen::Vector3d& uvw, double* value,
                                           double* jacobian) const {
  check_parameter(uvw);
  int first[3];
  double basis[3][4][4];
  for (int a = 0; a < 3; ++a) basis_along<1>(a, uvw[a], &first[a], basis[a]);
  const int dim = dimension();
  for (int d = 0; d < dim; ++d) value[d] = 0.0;
  for (int d = 0; d < 3 * dim; ++d) jacobian[d] = 0.0;
  for (int m2 = 0; m2 < 4; ++m2) {
    for (int m1 = 0; m1 < 4; ++m1) {
      const int row0 = control_index(first[0], first[1] + m1, first[2] + m2);
      for (int m0 = 0; m0 < 4; ++m0) {
        const double* n0 = basis[0][m0];
        const double* n1 = basis[1][m1];
        const double* n2 = basis[2][m2];
        const double b = n0[0] * n1[0] * n2[0];
        const double bu = n0[1] * n1[0] * n2[0];
        const double bv = n0[0] * n1[1] * n2[0];
        const double bw = n0[0] * n1[0] * n2[1];
        for (int d = 0; d < dim; ++d) {
          const double p = control_points_(row0 + m0, d);
          value[d] += b * p;
          jacobian[d] += bu * p;
          jacobian[d + dim] += bv * p;
          jacobian[d + 2 * dim] += bw * p;
        }
      }
    }
  }
}

Eigen::MatrixXd BsplineVolume::jacobian(const Eigen::Vector3d& uvw) const {
  double value[4];
  Eigen::MatrixXd jac(dimension(), 3);
  evaluate_with_jacobian(uvw, value, jac.data());
  return jac;
}

Eigen::MatrixXd BsplineVolume::evaluate_batch(const Eigen::MatrixX3d& uvw) const {
  Eigen::MatrixXd out(uvw.rows(), dimension());
  for (Eigen::Index i = 0; i < uvw.rows(); ++i) {
    double value[4];
    try {
      evaluate_to(uvw.row(i).transpose(), value);
    } catch (const Error& e) {
      throw Error("row " + std::to_string(i) + ": " + e.what());
    }
    for (int d = 0; d < dimension(); ++d) out(i, d) = value[d];
  }
  return out;
}

}  // namespace volspline::spline
