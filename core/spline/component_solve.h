// SPDX-License-Identifier: MIT
#pragma once
#include <vector>
#include <Eigen/Core>
#include "core/linalg/csr_matrix.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Outcome of solve_components.
struct ComponentSolveReport {
  int cg_iterations = 0;
  bool converged = false;
};

/// Solves the normal equations gram · x = rhs (gram n×n SPD, rhs n×k, n = num_functions()) of a
/// least-squares fit (Eq. 3.6 / 5.11) by CG with the SparsifiedCholesky preconditioner, warm-started
/// from the spline's current control-point components, and writes column c of x into component
/// components[c] of every control point. Precondition: components.size() == rhs.cols().
ComponentSolveReport solve_components(TSpline& spline, const linalg::CsrMatrix& gram, const Eigen::MatrixXd& rhs,
                                      const std::vector<int>& components, double tolerance, int max_iterations);

}  // namespace volspline::spline
