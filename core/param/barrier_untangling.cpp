// SPDX-License-Identifier: MIT
#include "core/param/barrier_untangling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "core/param/foldover_kernel.h"

namespace volspline::param {

namespace {

double chi(double d, double eps) { return 0.5 * (d + std::sqrt(eps * eps + d * d)); }

// The curvature pairs of L-BFGS.
struct LbfgsMemory {
  std::vector<Eigen::VectorXd> s_list, y_list;
  std::vector<double> rho;
};

// L-BFGS (two-loop recursion, 7 pairs) with Armijo backtracking, from the pairs in memory
// (updated); returns the iterations done.
int lbfgs(const UntangleProblem& problem, Eigen::VectorXd& x, double eps, int max_iterations,
          LbfgsMemory& memory, double* energy = nullptr) {
  constexpr int kPairs = 7;
  std::vector<Eigen::VectorXd>& s_list = memory.s_list;
  std::vector<Eigen::VectorXd>& y_list = memory.y_list;
  std::vector<double>& rho = memory.rho;
  Eigen::VectorXd g;
  double f = problem.energy(x, eps, &g);
  // Whether the last step took the full step: then the next full step gets its gradient at once.
  bool full_step = true;
  int iteration = 0;
  for (; iteration < max_iterations; ++iteration) {
    Eigen::VectorXd q = g;
    std::vector<double> alpha(s_list.size());
    for (int m = static_cast<int>(s_list.size()) - 1; m >= 0; --m) {
      alpha[m] = rho[m] * s_list[m].dot(q);
      q -= alpha[m] * y_list[m];
    }
    // Without curvature pairs the first step moves the worst unknown by 1e-2 (units of x).
    if (!s_list.empty())
      q *= s_list.back().dot(y_list.back()) / y_list.back().squaredNorm();
    else
      q *= 1e-2 / std::max(g.lpNorm<Eigen::Infinity>(), 1e-300);
    for (std::size_t m = 0; m < s_list.size(); ++m) {
      const double beta = rho[m] * y_list[m].dot(q);
      q += (alpha[m] - beta) * s_list[m];
    }
    Eigen::VectorXd d = -q;
    double slope = g.dot(d);
    if (!(slope < 0.0)) {  // not a descent direction: restart from steepest descent
      s_list.clear();
      y_list.clear();
      rho.clear();
      d = -g * (1e-2 / std::max(g.lpNorm<Eigen::Infinity>(), 1e-300));
      slope = g.dot(d);
      if (!(slope < 0.0)) break;
    }
    Eigen::VectorXd x_new, g_new;
    double f_new = f;
    bool accepted = false;
    // Along a prepared line the trials need only the energy; the gradient follows at the step taken.
    const bool line = problem.set_line && problem.line_energy;
    if (line) problem.set_line(x, d);
    // Without a line, the full step gets its gradient at once where the last step took it (the
    // energy is the same sum either way), and the other trials need only the energy.
    for (double t = 1.0; t > 1e-9; t *= 0.5) {
      x_new = x + t * d;
      const bool with_gradient = !line && t == 1.0 && (full_step || !problem.energy_below);
      const double bound = f + 1e-4 * t * slope;  // Armijo
      if (line)
        f_new = problem.line_energy(t, eps, nullptr);
      else if (with_gradient || !problem.energy_below)
        f_new = problem.energy(x_new, eps, with_gradient ? &g_new : nullptr);
      else
        f_new = problem.energy_below(x_new, eps, bound);
      if (f_new <= bound) {
        accepted = true;
        full_step = t == 1.0;
        if (line)
          f_new = problem.line_energy(t, eps, &g_new);
        else if (!with_gradient)
          f_new = problem.energy(x_new, eps, &g_new);
        break;
      }
    }
    if (!accepted) break;
    if (problem.settle) problem.settle(x_new);
    const Eigen::VectorXd s = x_new - x, y = g_new - g;
    const double sy = s.dot(y);
    if (sy > 1e-12 * s.norm() * y.norm()) {
      if (static_cast<int>(s_list.size()) == kPairs) {
        s_list.erase(s_list.begin());
        y_list.erase(y_list.begin());
        rho.erase(rho.begin());
      }
      s_list.push_back(s);
      y_list.push_back(y);
      rho.push_back(1.0 / sy);
    }
    const double decrease = f - f_new;
    x = std::move(x_new);
    g = std::move(g_new);
    f = f_new;
    if (decrease <= 1e-10 * std::abs(f)) {
      ++iteration;
      break;
    }
  }
  if (energy) *energy = f;
  return iteration;
}

}  // namespace

// The same kernel for one element and for a batch (bit-identical lanes; libm's cbrt would give
// other bits on other machines).
double foldover_free_energy(const Eigen::Matrix3d& j, double eps, double theta, Eigen::Matrix3d* gradient) {
  double energy;
  detail::foldover_kernel<1>(j.data(), eps, theta, &energy, gradient ? gradient->data() : nullptr);
  return energy;
}

void foldover_free_energy_batch(const double* j, double eps, double theta, double* energy, double* gradient) {
#if defined(VOLSPLINE_AVX2_KERNELS)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) return detail::foldover_kernel4_avx2(j, eps, theta, energy, gradient);
#endif
  detail::foldover_kernel<kFoldoverBatch>(j, eps, theta, energy, gradient);
}

namespace detail {

void hex_corner_terms(const double (*p)[3], double inv_h, double eps2, double theta, unsigned corners, double* e,
                      double (*grad)[3]) {
#if defined(VOLSPLINE_AVX512_KERNELS)
  static const bool avx512 = __builtin_cpu_supports("avx512f");
  if (avx512) return hex_corner_kernel_avx512(p, inv_h, eps2, theta, corners, e, grad);
#endif
#if defined(VOLSPLINE_AVX2_KERNELS)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) return hex_corner_kernel_avx2(p, inv_h, eps2, theta, corners, e, grad);
#endif
  hex_corner_kernel(p, inv_h, eps2, theta, corners, e, grad);
}

void hex_corner_terms2(const double (*const p[2])[3], const double inv_h[2], double eps2, double theta,
                       const unsigned corners[2], double* const e[2], double (*const grad[2])[3]) {
#if defined(VOLSPLINE_AVX512_KERNELS)
  static const bool avx512 = __builtin_cpu_supports("avx512f");
  if (avx512) return hex_corner_kernel2_avx512(p, inv_h, eps2, theta, corners, e, grad);
#endif
#if defined(VOLSPLINE_AVX2_KERNELS)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) return hex_corner_kernel2_avx2(p, inv_h, eps2, theta, corners, e, grad);
#endif
  for (int h = 0; h < 2; ++h)
    hex_corner_kernel(p[h], inv_h[h], eps2, theta, corners[h], e[h], grad && grad[0] ? grad[h] : nullptr);
}

}  // namespace detail

int minimize_lbfgs(const UntangleProblem& problem, double eps, int max_iterations, Eigen::VectorXd& x,
                   double* energy) {
  LbfgsMemory memory;
  return lbfgs(problem, x, eps, max_iterations, memory, energy);
}

int untangle(const UntangleProblem& problem, Eigen::VectorXd& x, const UntangleOptions& options) {
  int iterations = 0;
  // ε continuation of Garanzha et al. 2021 (§3): ε shrinks with the energy decrease, and
  // vanishes once every determinant exceeds μ.
  double d_min = problem.min_det(x);
  double eps = d_min > 0.0 ? 1e-8 : first_barrier_eps(d_min);
  double e_prev = problem.energy(x, eps, nullptr);
  double best_d_min = -std::numeric_limits<double>::infinity();
  int stalled = 0;
  LbfgsMemory memory;
  for (int step = 0; step < options.max_steps; ++step) {
    if (options.keep_curvature == UntangleOptions::KeepCurvature::Off) memory = LbfgsMemory();
    iterations += lbfgs(problem, x, eps, options.max_inner, memory);
    const double e = problem.energy(x, eps, nullptr);
    d_min = problem.min_det(x);
    const double sigma = std::max(1.0 - e / e_prev, options.min_sigma);
    const double mu = (1.0 - sigma) * chi(d_min, eps);
    eps = d_min < mu ? 2.0 * std::sqrt(mu * (mu - d_min)) : 1e-8;
    const bool settled = std::abs(e_prev - e) <= 1e-4 * std::abs(e);
    e_prev = e;
    if ((d_min > 0.0 && settled) || d_min > options.stop_min_det) break;
    // An element whose unknowns cannot reach a valid shape (e.g. a hex corner of fixed nodes
    // but one): once the worst determinant stops rising, more steps only sharpen the barrier.
    stalled = d_min > best_d_min + 1e-3 ? 0 : stalled + 1;
    best_d_min = std::max(best_d_min, d_min);
    if (d_min <= 0.0 && stalled >= 4) break;
  }
  return iterations;
}

}  // namespace volspline::param
