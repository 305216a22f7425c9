// SPDX-License-Identifier: MIT
#include "core/spline/component_solve.h"

#include <cassert>
#include <utility>

#include "core/linalg/conjugate_gradient.h"
#include "core/spline/sparsified_cholesky.h"

namespace volspline::spline {

ComponentSolveResult solve_normal_equations(linalg::CsrMatrix gram, const Eigen::MatrixXd& rhs, Eigen::MatrixXd& x,
                                            double tolerance, int max_iterations, int threads) {
  assert(rhs.rows() == gram.rows() && x.rows() == rhs.rows() && x.cols() == rhs.cols());
  linalg::ConjugateGradient<SparsifiedCholesky> cg;
  cg.set_tolerance(tolerance);
  cg.set_max_iterations(max_iterations);
  cg.set_threads(threads);
  cg.compute(gram);
  gram = linalg::CsrMatrix();
  x = cg.solve(rhs, x);
  return {cg.iterations(), cg.info() == linalg::SolverInfo::Success};
}

ComponentSolveResult solve_components(TSpline& spline, linalg::CsrMatrix gram, const Eigen::MatrixXd& rhs,
                                      const std::vector<int>& components, double tolerance, int max_iterations) {
  const int k = static_cast<int>(components.size());
  assert(rhs.cols() == k && rhs.rows() == spline.num_functions());
  Eigen::MatrixXd x(rhs.rows(), k);
  for (int c = 0; c < k; ++c) x.col(c) = spline.points().col(components[c]);
  const ComponentSolveResult result = solve_normal_equations(std::move(gram), rhs, x, tolerance, max_iterations);
  Eigen::MatrixXd points = spline.points();
  for (int c = 0; c < k; ++c) points.col(components[c]) = x.col(c);
  // Per-cell polynomials would be rebuilt for the new points; the function lists are cheaper.
  if (spline.has_cell_polynomials())
    spline = TSpline(spline.knots(), spline.weights(), std::move(points), TSplineAcceleration::FunctionLists);
  else
    spline.set_points(std::move(points));
  return result;
}

}  // namespace volspline::spline
