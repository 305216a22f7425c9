// SPDX-License-Identifier: MIT
#pragma once

#include <cmath>
#include <functional>
#include <limits>

#include <Eigen/Core>

namespace volspline::param {

/// Per-element energy of "Foldover-free maps in 50 lines of code" (Garanzha et al. 2021):
/// f_ε(J) = (1 − θ)·tr(JᵀJ)/χ(det J, ε)^(2/3) + θ·(det² J + 1)/χ(det J, ε) with
/// χ(D, ε) = (D + √(ε² + D²))/2 > 0, finite for folded elements (det J ≤ 0). j: the element's
/// Jacobian against its reference shape (3×3); theta in [0, 1); gradient (if not null): ∂f/∂J.
double foldover_free_energy(const Eigen::Matrix3d& j, double eps, double theta, Eigen::Matrix3d* gradient);

/// Elements per call of foldover_free_energy_batch.
constexpr int kFoldoverBatch = 4;

/// foldover_free_energy of kFoldoverBatch elements at once: j[k·4 + l] is entry k (column-major)
/// of element l's J, energy[l] its energy, gradient (if not null) ∂f/∂J laid out like j. Runs
/// AVX2 code where the CPU has it; every lane gives the same bits as foldover_free_energy.
void foldover_free_energy_batch(const double* j, double eps, double theta, double* energy, double* gradient);

/// A sum of foldover_free_energy terms (plus any smooth extra term) over unknowns x.
struct UntangleProblem {
  /// Energy at x with barrier parameter ε; writes ∂E/∂x to gradient if not null.
  std::function<double(const Eigen::VectorXd& x, double eps, Eigen::VectorXd* gradient)> energy;
  /// Smallest det J over the elements at x.
  std::function<double(const Eigen::VectorXd& x)> min_det;
  /// Optional (both or neither), for energies whose element Jacobians are linear in x:
  /// set_line(x, d) prepares the line x + t·d once per L-BFGS step, then line_energy(t, ε,
  /// gradient) equals energy(x + t·d, ε, gradient) up to rounding, without new Jacobians per
  /// trial of the line search.
  std::function<void(const Eigen::VectorXd& x, const Eigen::VectorXd& d)> set_line;
  std::function<double(double t, double eps, Eigen::VectorXd* gradient)> line_energy;
  /// Optional, for an energy that is a sum of nonnegative terms: energy_below(x, ε, bound)
  /// equals energy(x, ε) when that is at most bound, and is some value above bound otherwise
  /// (the sum may stop as soon as it passes bound): the line search's rejected trials need no more.
  std::function<double(const Eigen::VectorXd& x, double eps, double bound)> energy_below;
  /// Optional: settle(x) replaces an accepted L-BFGS iterate by an equivalent point, with the
  /// energy and gradient of the last evaluation at x (e.g. sliding unknowns moved onto the
  /// surface point they stand for), so that the next steps start from it.
  std::function<void(Eigen::VectorXd& x)> settle;
};

/// Options of untangle.
struct UntangleOptions {
  int max_steps = 40;  ///< ε-continuation steps, ≥ 1
  int max_inner = 30;  ///< L-BFGS iterations per step, ≥ 1
  /// Stop as soon as every det J exceeds this after a step (untangled is enough; the energy
  /// need not settle); +∞ = run the continuation to its end.
  double stop_min_det = std::numeric_limits<double>::infinity();
  /// Keep the L-BFGS curvature pairs from one ε step to the next (the energy changes little
  /// with ε); Off restarts each step from a steepest-descent step.
  enum class KeepCurvature { Off, On } keep_curvature = KeepCurvature::Off;
  /// Least σ of the ε update μ = (1 − σ)·χ(min det J, ε), in (0, 1). The paper's 0.1 makes ε
  /// creep down (the energy grows as ε shrinks, so its decrease never sets the pace): ~35 steps
  /// on bimba's grid instead of ~8 with 0.5.
  double min_sigma = 0.5;
};

/// The ε continuation's first ε where the least corner determinant d_min is ≤ 0 (Garanzha et
/// al. 2021, §3): 2·√(0.1·(0.1 − d_min)).
inline double first_barrier_eps(double d_min) { return 2.0 * std::sqrt(0.1 * (0.1 - d_min)); }

/// One ε step of untangle: at most max_iterations L-BFGS iterations (two-loop recursion, 7
/// curvature pairs, Armijo backtracking; the first step moves the worst unknown by 1e-2) on
/// problem.energy(·, eps) from x, updated in place; stops early when the energy decrease falls
/// under 1e-10 of the energy. Returns the iterations done. energy (if not null) gets the energy
/// at the returned x from the evaluation that accepted it (problem.energy's own value unless the
/// problem sets `settle` or the line functions: then the accepted point was not evaluated as such).
int minimize_lbfgs(const UntangleProblem& problem, double eps, int max_iterations, Eigen::VectorXd& x,
                   double* energy = nullptr);

/// Minimizes the problem's energy from x (updated in place) by L-BFGS with the ε continuation
/// of Garanzha et al. 2021: ε shrinks with the energy decrease and vanishes once every element
/// has det J > μ. Stops when det J > 0 everywhere and the energy settles, when the smallest
/// det J stops rising while still ≤ 0 (some element cannot unfold), or after max_steps.
/// Returns the L-BFGS iterations done.
int untangle(const UntangleProblem& problem, Eigen::VectorXd& x, const UntangleOptions& options = {});

}  // namespace volspline::param
