// SPDX-License-Identifier: MIT
#pragma once
#include <vector>
#include <Eigen/Core>
#include "core/linalg/csr_matrix.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Outcome of solve_components.
struct ComponentSolveResult {
  int cg_iterations = 0;
  bool converged = false;
};

/// Solves the normal equations gram · x = rhs (gram n×n SPD, only its diagonal and upper triangle
/// are read, so it may hold just those; rhs n×k) of a least-squares fit (Eq. 3.6 / 5.11) by CG with
/// the SparsifiedCholesky preconditioner, warm-started from x0 (n×k), and returns x. gram is
/// consumed: it is released once CG has copied it, which keeps the peak memory at one matrix.
/// threads (≥ 1): for the CG's matrix products; the result is the same for every count.
/// Precondition: x0 and rhs have gram.rows() rows and the same columns.
ComponentSolveResult solve_normal_equations(linalg::CsrMatrix gram, const Eigen::MatrixXd& rhs, Eigen::MatrixXd& x,
                                            double tolerance, int max_iterations, int threads = 1);

/// solve_normal_equations warm-started from the spline's control-point components (n =
/// num_functions()), writing column c of the solution into component components[c] of every
/// control point. Precondition: components.size() == rhs.cols().
ComponentSolveResult solve_components(TSpline& spline, linalg::CsrMatrix gram, const Eigen::MatrixXd& rhs,
                                      const std::vector<int>& components, double tolerance, int max_iterations);

}  // namespace volspline::spline
