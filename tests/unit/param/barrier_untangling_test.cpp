// SPDX-License-Identifier: MIT
#include "core/param/barrier_untangling.h"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/LU>

#include "core/param/foldover_kernel.h"

using namespace volspline;

namespace {

// Two unit cubes jittered independently (one may fold where the other does not), with their own
// edge lengths and corner flags, for the kernel tests; with `crushed`, now and then the second
// crushed so far that χ underflows.
struct HexPair {
  double p[2][8][3];
  unsigned corners[2];
  double inv_h[2];
  double eps2, theta;
};
HexPair random_hex_pair(std::mt19937_64& rng, int round, bool crushed) {
  std::normal_distribution<double> jitter(0.0, 1.0);
  HexPair out;
  for (int h = 0; h < 2; ++h)
    for (int q = 0; q < 8; ++q)
      for (int d = 0; d < 3; ++d) out.p[h][q][d] = ((q >> d) & 1) + ((round + h) % 4 == 0 ? 0.7 : 0.2) * jitter(rng);
  if (crushed && round % 50 == 0)
    for (int q = 0; q < 8; ++q)
      for (int d = 0; d < 3; ++d) out.p[1][q][d] *= (q >> d) & 1 ? -1000.0 : 1000.0;
  out.corners[0] = round % 5 == 0 ? 0xFFu : static_cast<unsigned>(rng() & 0xFF);
  out.corners[1] = static_cast<unsigned>(rng() & 0xFF);
  out.inv_h[0] = round % 2 == 0 ? 1.0 : 3.7;
  out.inv_h[1] = 0.8;
  out.eps2 = round % 3 == 0 ? 1e-16 : 0.04;
  out.theta = round % 7 == 0 ? 0.0 : 0.5;
  return out;
}

// Corner x with fixed neighbours e0, e1, e2: J = [e_a − x]. A start beyond the plane of the
// neighbours has det < 0; the unique fold-free region is on the origin's side.
Eigen::Matrix3d corner_jacobian(const Eigen::VectorXd& x) {
  Eigen::Matrix3d j;
  for (int a = 0; a < 3; ++a) j.col(a) = Eigen::Matrix3d::Identity().col(a) - x;
  return j;
}

param::UntangleProblem corner_problem() {
  param::UntangleProblem problem;
  problem.energy = [](const Eigen::VectorXd& x, double eps, Eigen::VectorXd* gradient) {
    Eigen::Matrix3d g;
    const double e = param::foldover_free_energy(corner_jacobian(x), eps, 0.5, gradient ? &g : nullptr);
    if (gradient) *gradient = -g.rowwise().sum();
    return e;
  };
  problem.min_det = [](const Eigen::VectorXd& x) { return corner_jacobian(x).determinant(); };
  return problem;
}

}  // namespace

TEST_CASE("the foldover-free energy's gradient matches central differences, folded or not") {
  Eigen::Matrix3d valid;
  valid << 1.1, 0.2, -0.1, 0.05, 0.9, 0.3, -0.2, 0.1, 1.2;
  Eigen::Matrix3d folded = valid;
  folded.col(0) = -folded.col(0);
  for (const Eigen::Matrix3d& j : {valid, folded}) {
    for (double eps : {1e-2, 0.5}) {
      Eigen::Matrix3d g;
      param::foldover_free_energy(j, eps, 0.5, &g);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          const double h = 1e-6;
          Eigen::Matrix3d a = j, b = j;
          a(r, c) += h;
          b(r, c) -= h;
          const double fd = (param::foldover_free_energy(a, eps, 0.5, nullptr) -
                             param::foldover_free_energy(b, eps, 0.5, nullptr)) / (2 * h);
          // Central differences: O(h²) truncation on an energy of size ~1e2 at most.
          CHECK(g(r, c) == doctest::Approx(fd).epsilon(1e-5).scale(1.0));
        }
    }
  }
  // The energy of the identity with ε → 0 is (1 − θ)·3 + θ·2: tr = 3, det = 1, χ = 1.
  CHECK(param::foldover_free_energy(Eigen::Matrix3d::Identity(), 1e-12, 0.5, nullptr) == doctest::Approx(2.5).epsilon(1e-12));
}

TEST_CASE("the energy's own cube root is within 3 ulp of libm's from 1e-300 to 1e300") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> exponent(-300.0, 300.0), mantissa(1.0, 10.0);
  for (int i = 0; i < 100000; ++i) {
    const double y = mantissa(rng) * std::pow(10.0, exponent(rng));
    const double r = param::detail::cbrt_positive(y), ref = std::cbrt(y);
    REQUIRE(std::abs(r - ref) <= 3.0 * (std::nextafter(ref, 2.0 * ref) - ref));
  }
  CHECK(param::detail::cbrt_positive(8.0) == 2.0);
  CHECK(param::detail::cbrt_positive(1.0) == 1.0);
}

TEST_CASE("the batch energy (AVX2 where the CPU has it) gives every lane the bits of the single one") {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> entry(0.0, 1.0);
  for (int round = 0; round < 2000; ++round) {
    double in[9 * param::kFoldoverBatch], energy[param::kFoldoverBatch], gradient[9 * param::kFoldoverBatch];
    std::array<Eigen::Matrix3d, param::kFoldoverBatch> j;
    for (int l = 0; l < param::kFoldoverBatch; ++l) {
      j[l] = Eigen::Matrix3d::Identity() + 0.7 * Eigen::Matrix3d::NullaryExpr([&] { return entry(rng); });
      // Now and then a lane whose χ underflows to 0 (the cube root's clamp to the least normal).
      if (round % 50 == 0 && l == round / 50 % param::kFoldoverBatch) j[l] = -1000.0 * Eigen::Matrix3d::Identity();
      for (int k = 0; k < 9; ++k) in[k * param::kFoldoverBatch + l] = j[l].data()[k];
    }
    const double eps = round % 3 == 0 ? 1e-8 : 0.1;
    param::foldover_free_energy_batch(in, eps, 0.5, energy, gradient);
    for (int l = 0; l < param::kFoldoverBatch; ++l) {
      Eigen::Matrix3d g;
      const double e = param::foldover_free_energy(j[l], eps, 0.5, &g);
      REQUIRE(std::memcmp(&e, &energy[l], sizeof e) == 0);
      for (int k = 0; k < 9; ++k) REQUIRE(std::memcmp(&g.data()[k], &gradient[k * param::kFoldoverBatch + l], sizeof(double)) == 0);
    }
  }
}

TEST_CASE("the hex corner terms (AVX2 where the CPU has it) give the bits of the portable kernel") {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> jitter(0.0, 1.0);
  for (int round = 0; round < 4000; ++round) {
    // A unit cube's nodes moved by up to 0.7 (folded corners among them), some corners flagged.
    double p[8][3];
    for (int q = 0; q < 8; ++q)
      for (int d = 0; d < 3; ++d) p[q][d] = ((q >> d) & 1) + (round % 4 == 0 ? 0.7 : 0.2) * jitter(rng);
    const unsigned corners = round % 5 == 0 ? 0xFFu : static_cast<unsigned>(rng() & 0xFF);
    const double inv_h = round % 2 == 0 ? 1.0 : 3.7, eps2 = round % 3 == 0 ? 1e-16 : 0.04, theta = round % 7 == 0 ? 0.0 : 0.5;
    double e[8], grad[8][3], e_ref[8], grad_ref[8][3];
    param::detail::hex_corner_terms(p, inv_h, eps2, theta, corners, e, grad);
    param::detail::hex_corner_kernel(p, inv_h, eps2, theta, corners, e_ref, grad_ref);
    REQUIRE(std::memcmp(e, e_ref, sizeof e) == 0);
    REQUIRE(std::memcmp(grad, grad_ref, sizeof grad) == 0);
    double e_only[8];
    param::detail::hex_corner_terms(p, inv_h, eps2, theta, corners, e_only, nullptr);
    REQUIRE(std::memcmp(e_only, e_ref, sizeof e_only) == 0);
  }
}

TEST_CASE("the hex corner terms of two hexes in one call give the bits of two portable calls") {
  std::mt19937_64 rng(11);
  for (int round = 0; round < 2000; ++round) {
    HexPair pair = random_hex_pair(rng, round, false);
    const auto& p = pair.p;
    const auto& corners = pair.corners;
    const auto& inv_h = pair.inv_h;
    const double eps2 = pair.eps2, theta = pair.theta;
    double e[2][8], grad[2][8][3], e_ref[2][8], grad_ref[2][8][3], e_only[2][8];
    const double(*pp[2])[3] = {p[0], p[1]};
    double* const ee[2] = {e[0], e[1]};
    double(*const gg[2])[3] = {grad[0], grad[1]};
    param::detail::hex_corner_terms2(pp, inv_h, eps2, theta, corners, ee, gg);
    double* const ee_only[2] = {e_only[0], e_only[1]};
    double(*const no_grad[2])[3] = {nullptr, nullptr};
    param::detail::hex_corner_terms2(pp, inv_h, eps2, theta, corners, ee_only, round % 2 ? no_grad : nullptr);
    for (int h = 0; h < 2; ++h) {
      param::detail::hex_corner_kernel(p[h], inv_h[h], eps2, theta, corners[h], e_ref[h], grad_ref[h]);
      REQUIRE(std::memcmp(e[h], e_ref[h], sizeof e[h]) == 0);
      REQUIRE(std::memcmp(grad[h], grad_ref[h], sizeof grad[h]) == 0);
      REQUIRE(std::memcmp(e_only[h], e_ref[h], sizeof e_only[h]) == 0);
    }
  }
}

#if defined(VOLSPLINE_AVX2_KERNELS) || defined(VOLSPLINE_AVX512_KERNELS)
TEST_CASE("every SIMD build of the hex corner kernel that the CPU runs gives the bits of the portable kernel") {
  // The dispatch of hex_corner_terms picks one build; each is checked here on its own.
  using Kernel1 = void (*)(const double(*)[3], double, double, double, unsigned, double*, double(*)[3]);
  using Kernel2 = void (*)(const double(*const[2])[3], const double[2], double, double, const unsigned[2],
                           double* const[2], double(*const[2])[3]);
  std::vector<std::pair<Kernel1, Kernel2>> builds;
#if defined(VOLSPLINE_AVX2_KERNELS)
  if (__builtin_cpu_supports("avx2"))
    builds.emplace_back(param::detail::hex_corner_kernel_avx2, param::detail::hex_corner_kernel2_avx2);
#endif
#if defined(VOLSPLINE_AVX512_KERNELS)
  if (__builtin_cpu_supports("avx512f"))
    builds.emplace_back(param::detail::hex_corner_kernel_avx512, param::detail::hex_corner_kernel2_avx512);
#endif
  for (const auto& [one, two] : builds) {
    std::mt19937_64 rng(17);
    for (int round = 0; round < 2000; ++round) {
      HexPair pair = random_hex_pair(rng, round, true);
      const auto& p = pair.p;
      const auto& corners = pair.corners;
      const auto& inv_h = pair.inv_h;
      const double eps2 = pair.eps2, theta = pair.theta;
      double e[2][8], grad[2][8][3], e_ref[2][8], grad_ref[2][8][3], e_only[2][8], e_one[8], grad_one[8][3];
      const double(*pp[2])[3] = {p[0], p[1]};
      double* const ee[2] = {e[0], e[1]};
      double(*const gg[2])[3] = {grad[0], grad[1]};
      two(pp, inv_h, eps2, theta, corners, ee, gg);
      double* const ee_only[2] = {e_only[0], e_only[1]};
      two(pp, inv_h, eps2, theta, corners, ee_only, nullptr);
      for (int h = 0; h < 2; ++h) {
        param::detail::hex_corner_kernel(p[h], inv_h[h], eps2, theta, corners[h], e_ref[h], grad_ref[h]);
        REQUIRE(std::memcmp(e[h], e_ref[h], sizeof e[h]) == 0);
        REQUIRE(std::memcmp(grad[h], grad_ref[h], sizeof grad[h]) == 0);
        REQUIRE(std::memcmp(e_only[h], e_ref[h], sizeof e_only[h]) == 0);
        one(p[h], inv_h[h], eps2, theta, corners[h], e_one, grad_one);
        REQUIRE(std::memcmp(e_one, e_ref[h], sizeof e_one) == 0);
        REQUIRE(std::memcmp(grad_one, grad_ref[h], sizeof grad_one) == 0);
      }
    }
  }
}
#endif

TEST_CASE("untangle unfolds a single free corner of an inverted tetrahedron") {
  const param::UntangleProblem problem = corner_problem();
  Eigen::VectorXd x = Eigen::Vector3d(0.8, 0.8, 0.8);
  REQUIRE(problem.min_det(x) < 0.0);
  param::untangle(problem, x);
  CHECK(problem.min_det(x) > 0.0);
}

TEST_CASE("untangle with kept curvature pairs and a faster ε decrease also unfolds the corner") {
  // Same problem as above; the options only change the pace, not the fold-free outcome.
  const param::UntangleProblem problem = corner_problem();
  param::UntangleOptions options;
  options.keep_curvature = param::UntangleOptions::KeepCurvature::On;
  options.min_sigma = 0.75;
  options.max_inner = 5;
  options.stop_min_det = 0.0;
  Eigen::VectorXd x = Eigen::Vector3d(0.8, 0.8, 0.8);
  REQUIRE(problem.min_det(x) < 0.0);
  const int iterations = param::untangle(problem, x, options);
  CHECK(problem.min_det(x) > 0.0);
  CHECK(iterations <= options.max_steps * options.max_inner);
  // Deterministic: the same start gives the same bits.
  Eigen::VectorXd again = Eigen::Vector3d(0.8, 0.8, 0.8);
  param::untangle(problem, again, options);
  CHECK(again == x);
}

TEST_CASE("untangle along prepared lines (linear Jacobians) takes the same steps as plain energy calls") {
  // J = [e_a − x] is linear in x: along x + t·d it is J(x) − t·[d d d].
  param::UntangleProblem problem = corner_problem();
  Eigen::Vector3d line_x, line_d;
  int line_calls = 0;
  problem.set_line = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& d) {
    line_x = x;
    line_d = d;
  };
  problem.line_energy = [&](double t, double eps, Eigen::VectorXd* gradient) {
    ++line_calls;
    Eigen::Matrix3d j = corner_jacobian(line_x);
    for (int a = 0; a < 3; ++a) j.col(a) -= t * line_d;
    Eigen::Matrix3d g;
    const double e = param::foldover_free_energy(j, eps, 0.5, gradient ? &g : nullptr);
    if (gradient) *gradient = -g.rowwise().sum();
    return e;
  };
  param::UntangleOptions options;
  options.keep_curvature = param::UntangleOptions::KeepCurvature::On;
  options.max_inner = 5;
  Eigen::VectorXd x = Eigen::Vector3d(0.8, 0.8, 0.8), plain = x;
  const int iterations = param::untangle(problem, x, options);
  const int plain_iterations = param::untangle(corner_problem(), plain, options);
  CHECK(line_calls > 0);
  CHECK(problem.min_det(x) > 0.0);
  CHECK(iterations == plain_iterations);
  // The same trials: only the rounding of J(x) + t·J_d against J(x + t·d) differs.
  CHECK((x - plain).norm() < 1e-9);
}

TEST_CASE("untangle with energy_below (the line search's trials bounded by Armijo's) takes the same steps") {
  // Two independent corners, x = (corner 0, corner 1): the energy is the sum of their two terms.
  const auto corner_energy = [](const Eigen::VectorXd& x, int c, double eps, Eigen::VectorXd* gradient) {
    Eigen::Matrix3d g;
    const double e = param::foldover_free_energy(corner_jacobian(x.segment<3>(3 * c)), eps, 0.5, gradient ? &g : nullptr);
    if (gradient) gradient->segment<3>(3 * c) = -g.rowwise().sum();
    return e;
  };
  param::UntangleProblem plain;
  plain.energy = [&](const Eigen::VectorXd& x, double eps, Eigen::VectorXd* gradient) {
    if (gradient) gradient->resize(6);
    double e = 0.0;
    for (int c = 0; c < 2; ++c) e += corner_energy(x, c, eps, gradient);
    return e;
  };
  plain.min_det = [](const Eigen::VectorXd& x) {
    return std::min(corner_jacobian(x.head<3>()).determinant(), corner_jacobian(x.tail<3>()).determinant());
  };
  param::UntangleProblem bounded = plain;
  int calls = 0, stopped = 0;
  // Past the bound, any value above it (here bound + 1, not the energy) must do.
  bounded.energy_below = [&](const Eigen::VectorXd& x, double eps, double bound) {
    ++calls;
    const double e = plain.energy(x, eps, nullptr);
    stopped += e > bound;
    return e > bound ? bound + 1.0 : e;
  };
  Eigen::VectorXd start(6);
  start << 0.8, 0.8, 0.8, 0.9, -0.3, 0.7;
  Eigen::VectorXd x = start, y = start;
  const int iterations = param::untangle(plain, x);
  const int bounded_iterations = param::untangle(bounded, y);
  CHECK(plain.min_det(x) > 0.0);
  CHECK(calls > 0);
  CHECK(stopped > 0);
  CHECK(bounded_iterations == iterations);
  CHECK(y == x);
}
