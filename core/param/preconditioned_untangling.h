// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/SparseCore>

#include "core/param/barrier_untangling.h"

namespace volspline::param {

/// Minimizes problem.energy(·, eps) (one ε step of the continuation of Garanzha et al. 2021)
/// from x, updated in place, by at most max_iterations iterations of L-BFGS whose initial
/// inverse Hessian is γ·M⁻¹ (γ = sᵀy / yᵀM⁻¹y of the newest pair), with Armijo backtracking;
/// stops early when the energy decrease falls under 1e-10 of the energy. x: 3·n unknowns (x, y,
/// z per node); metric M: n×n SPD applied to each coordinate (factorized by sparse Cholesky),
/// e.g. the edge Laplacian of a mesh with its fixed nodes eliminated, or 0×0 for the identity
/// (plain L-BFGS; the first step then moves the worst unknown by 1e-2, as untangle). Starts
/// without curvature pairs. Returns the iterations done.
int minimize_preconditioned(const UntangleProblem& problem, const Eigen::SparseMatrix<double>& metric, double eps,
                            int max_iterations, Eigen::VectorXd& x);

}  // namespace volspline::param
