// SPDX-License-Identifier: MIT
#include "core/spline/jacobian_repair.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/spline/tspline_fitting.h"

namespace volspline::spline {

namespace {

struct PointState {
  std::vector<double> det;     // det J per point
  double penalty = 0.0;        // Σ_s (max(0, t_s − det_s) / scale_s)²
  int negative = 0;
  double min_scaled = 1.0;
};

// target[s] = τ·scale_s and scale[s] = |j0||j1||j2| of the fitted spline, fixed during the
// repair so that the penalty is a polynomial in the control points (Gauss–Newton's model).
PointState evaluate_points(const TSpline& spline, const std::vector<Eigen::Vector3d>& points,
                           const std::vector<double>& target, const std::vector<double>& scale) {
  PointState state;
  state.det.resize(points.size());
  double value[3];
  Eigen::Matrix3d jac;
  for (std::size_t s = 0; s < points.size(); ++s) {
    spline.evaluate_with_jacobian(points[s], TSplineForm::SemiStandard, value, jac.data());
    const double det = jac.determinant();
    const double norms = jac.col(0).norm() * jac.col(1).norm() * jac.col(2).norm();
    const double q = norms > 0.0 ? det / norms : -1.0;
    state.det[s] = det;
    if (q <= 0.0) ++state.negative;
    state.min_scaled = std::min(state.min_scaled, q);
    if (det < target[s]) state.penalty += (target[s] - det) * (target[s] - det) / (scale[s] * scale[s]);
  }
  return state;
}

// The Gauss–Newton rows of the violated points, (det J_s + cof(J_s) Σ_i w_i ∇B_i(u_s) · δp_i) /
// scale_s ≥ τ, over the interior functions that act there (columns 3c .. 3c + 2 for used[c]).
struct GaussNewtonRows {
  std::vector<linalg::Triplet> triplets;
  std::vector<double> rhs;
  std::vector<int> used;
};

// column_of: per function, −1 on entry and set for the used ones (the caller resets them).
GaussNewtonRows violated_rows(const TSpline& spline, const std::vector<Eigen::Vector3d>& points,
                              const std::vector<double>& target, const std::vector<double>& scale,
                              const PointState& state, const std::vector<char>& interior, std::vector<int>& column_of) {
  GaussNewtonRows out;
  std::array<std::vector<int>, 3> basis_ids;
  std::array<std::vector<double>, 3> basis_d;
  double value[3];
  Eigen::Matrix3d jac;
  for (std::size_t s = 0; s < points.size(); ++s) {
    if (state.det[s] >= target[s]) continue;
    spline.evaluate_with_jacobian(points[s], TSplineForm::SemiStandard, value, jac.data());
    // cof(J)_{ra} = ∂ det J / ∂ J_{ra}.
    Eigen::Matrix3d cof;
    cof.col(0) = jac.col(1).cross(jac.col(2));
    cof.col(1) = jac.col(2).cross(jac.col(0));
    cof.col(2) = jac.col(0).cross(jac.col(1));
    for (int a = 0; a < 3; ++a) {
      std::array<int, 3> order = {0, 0, 0};
      order[a] = 1;
      spline.basis_at(points[s], order, basis_ids[a], basis_d[a]);
    }
    const int row = static_cast<int>(out.rhs.size());
    bool any = false;
    for (std::size_t m = 0; m < basis_ids[0].size(); ++m) {
      const int f = basis_ids[0][m];
      if (!interior[f]) continue;
      const Eigen::Vector3d grad(basis_d[0][m], basis_d[1][m], basis_d[2][m]);
      const Eigen::Vector3d g = spline.weights()(f) * (cof * grad) / scale[s];
      if (g.squaredNorm() == 0.0) continue;
      if (column_of[f] < 0) {
        column_of[f] = static_cast<int>(out.used.size());
        out.used.push_back(f);
      }
      for (int d = 0; d < 3; ++d) out.triplets.push_back({row, 3 * column_of[f] + d, g(d)});
      any = true;
    }
    if (any) out.rhs.push_back((target[s] - state.det[s]) / scale[s]);
  }
  return out;
}

// The least-squares step of the rows with Levenberg–Marquardt damping, which keeps the step
// inside the region where the lagged column norms and the linearization hold.
// triplets, rhs: those of GaussNewtonRows; num_used: its used functions.
Eigen::VectorXd damped_step(std::vector<linalg::Triplet> triplets, const std::vector<double>& rhs, int num_used) {
  const int cols = 3 * num_used;
  const int rows = static_cast<int>(rhs.size());
  Eigen::VectorXd diag = Eigen::VectorXd::Zero(cols);
  for (const auto& t : triplets) diag(t.col) += t.value * t.value;
  const double mean = diag.sum() / cols;
  Eigen::MatrixXd b = Eigen::Map<const Eigen::VectorXd>(rhs.data(), rows);
  for (int c = 0; c < cols; ++c) {
    triplets.push_back({rows + c, c, std::sqrt(0.01 * diag(c) + 1e-6 * mean)});
  }
  b.conservativeResize(rows + cols, 1);
  b.bottomRows(cols).setZero();
  const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(rows + cols, cols, triplets);
  const linalg::NormalEquations normal = linalg::normal_equations(a, b);
  // A Gauss–Newton step needs no accuracy beyond the model's: tolerance 1e-4.
  linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
  cg.set_tolerance(1e-4);
  cg.set_max_iterations(500);
  cg.compute(normal.ata);
  Eigen::VectorXd step = cg.solve(normal.atb.col(0));
  if (cg.info() == linalg::SolverInfo::NumericalIssue) {
    linalg::ConjugateGradient<linalg::JacobiPreconditioner> jacobi;
    jacobi.set_tolerance(1e-4);
    jacobi.set_max_iterations(500);
    jacobi.compute(normal.ata);
    step = jacobi.solve(normal.atb.col(0));
  }
  return step;
}

}  // namespace

JacobianRepairResult repair_jacobian(TSpline& result, const JacobianRepairOptions& options) {
  assert(result.dimension() == 3);
  // Function lists: changing the control points then costs nothing, while per-cell polynomials
  // would be rebuilt for every trial step.
  TSpline spline(result.knots(), result.weights(), result.points(), TSplineAcceleration::FunctionLists);
  assert(options.lattice >= 4 && options.min_scaled_jacobian > 0.0 && options.min_scaled_jacobian < 1.0);
  const double tau = options.min_scaled_jacobian;
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  std::vector<Eigen::Vector3d> points;
  const int lattice = options.lattice;
  for (int k = 1; k < lattice; ++k)
    for (int j = 1; j < lattice; ++j)
      for (int i = 1; i < lattice; ++i)
        points.push_back(lo + (hi - lo).cwiseProduct(Eigen::Vector3d(i, j, k) / lattice));
  JacobianRepairResult outcome;
  outcome.points = static_cast<int>(points.size());
  std::vector<double> target(points.size()), scale(points.size());
  {
    double value[3];
    Eigen::Matrix3d jac;
    double mean = 0.0;
    for (std::size_t s = 0; s < points.size(); ++s) {
      spline.evaluate_with_jacobian(points[s], TSplineForm::SemiStandard, value, jac.data());
      scale[s] = jac.col(0).norm() * jac.col(1).norm() * jac.col(2).norm();
      mean += scale[s] / points.size();
    }
    for (std::size_t s = 0; s < points.size(); ++s) {
      scale[s] = std::max(scale[s], 1e-6 * mean);
      target[s] = tau * scale[s];
    }
  }
  PointState state = evaluate_points(spline, points, target, scale);
  outcome.initial_negative = outcome.final_negative = state.negative;
  outcome.initial_min_scaled = outcome.final_min_scaled = state.min_scaled;

  const int n = spline.num_functions();
  std::vector<char> interior(n);
  for (int i = 0; i < n; ++i) interior[i] = !touches_exposed_face(spline.knots()[i], lo, hi, options.exposed_faces);
  std::vector<char> moved(n, 0);
  std::vector<int> column_of(n, -1);
  for (int iteration = 0; iteration < options.max_iterations && state.penalty > 0.0; ++iteration) {
    GaussNewtonRows rows = violated_rows(spline, points, target, scale, state, interior, column_of);
    const std::vector<int>& used = rows.used;
    if (used.empty()) break;
    const Eigen::VectorXd step = damped_step(std::move(rows.triplets), rows.rhs, static_cast<int>(used.size()));
    const Eigen::MatrixXd start = spline.points();
    bool accepted = false;
    for (double t = 1.0; t >= 1.0 / 16.0 && !accepted; t *= 0.5) {
      Eigen::MatrixXd trial = start;
      for (std::size_t c = 0; c < used.size(); ++c)
        trial.row(used[c]) += t * step.segment<3>(3 * c).transpose();
      spline.set_points(trial);
      PointState next = evaluate_points(spline, points, target, scale);
      if (next.penalty < state.penalty) {
        state = std::move(next);
        accepted = true;
      }
    }
    for (int f : used) column_of[f] = -1;
    if (!accepted) {
      spline.set_points(start);
      break;
    }
    for (int f : used) moved[f] = 1;
    outcome.iterations = iteration + 1;
  }
  if (outcome.iterations > 0) result.set_points(spline.points());
  outcome.final_negative = state.negative;
  outcome.final_min_scaled = state.min_scaled;
  outcome.moved_points = static_cast<int>(std::count(moved.begin(), moved.end(), 1));
  return outcome;
}

}  // namespace volspline::spline
