// SPDX-License-Identifier: MIT
#include "core/volume/local_cubic_fit.h"

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include <Eigen/QR>

#include "core/common/error.h"
#include "core/linalg/parallel_for.h"

namespace volspline::volume {

namespace {

// Exponents (i, j, k) of the 20 cubic monomials, ordered by degree so the first 10 (degree <= 2)
// alone give value, gradient and Hessian at the window centre.
struct Monomials {
  std::array<std::array<int, 3>, kNumCubicMonomials> exponents{};
  Monomials() {
    int m = 0;
    for (int degree = 0; degree <= 3; ++degree)
      for (int i = degree; i >= 0; --i)
        for (int j = degree - i; j >= 0; --j) exponents[m++] = {i, j, degree - i - j};
  }
};

constexpr int kNumQuadraticMonomials = 10;

double power(double base, int exponent) {
  double result = 1.0;
  for (int e = 0; e < exponent; ++e) result *= base;
  return result;
}

// d^n/dt^n of t^e at t, as a factor (0 if n > e).
double derivative_factor(double t, int e, int n) {
  if (n > e) return 0.0;
  double coefficient = 1.0;
  for (int q = 0; q < n; ++q) coefficient *= e - q;
  return coefficient * power(t, e - n);
}

// Value, gradient and Hessian of sum_m c_m u^i v^j w^k at point (Eq. 5.2 and its second derivatives).
void evaluate(const Monomials& monomials, const Eigen::VectorXd& c, const Eigen::Vector3d& point, double& value,
              Eigen::Vector3d& gradient, Eigen::Matrix3d& hessian) {
  value = 0.0;
  gradient.setZero();
  hessian.setZero();
  for (int m = 0; m < kNumCubicMonomials; ++m) {
    const auto& e = monomials.exponents[m];
    auto term = [&](int du, int dv, int dw) {
      return c[m] * derivative_factor(point[0], e[0], du) * derivative_factor(point[1], e[1], dv) *
             derivative_factor(point[2], e[2], dw);
    };
    value += term(0, 0, 0);
    gradient += Eigen::Vector3d(term(1, 0, 0), term(0, 1, 0), term(0, 0, 1));
    hessian(0, 0) += term(2, 0, 0);
    hessian(1, 1) += term(0, 2, 0);
    hessian(2, 2) += term(0, 0, 2);
    hessian(0, 1) += term(1, 1, 0);
    hessian(0, 2) += term(1, 0, 1);
    hessian(1, 2) += term(0, 1, 1);
  }
  hessian(1, 0) = hessian(0, 1);
  hessian(2, 0) = hessian(0, 2);
  hessian(2, 1) = hessian(1, 2);
}

}  // namespace

Eigen::MatrixXd cubic_fit_operator(int ring) {
  const Monomials monomials;
  const int side = 2 * ring + 1;
  // Eq. 5.3: one row P(u_j, v_j, w_j) per window voxel.
  Eigen::MatrixXd q(side * side * side, kNumCubicMonomials);
  int row = 0;
  for (int dz = -ring; dz <= ring; ++dz)
    for (int dy = -ring; dy <= ring; ++dy)
      for (int dx = -ring; dx <= ring; ++dx, ++row)
        for (int m = 0; m < kNumCubicMonomials; ++m) {
          const auto& e = monomials.exponents[m];
          q(row, m) = power(dx, e[0]) * power(dy, e[1]) * power(dz, e[2]);
        }
  // Eq. 5.4, via QR of Q rather than forming Q^T Q, for accuracy.
  return q.colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(q.rows(), q.rows()));
}

LocalCubicFit fit_local_cubics(const Volume& volume, const LocalCubicFitOptions& options,
                               const Progress& progress) {
  const int k = options.ring;
  if (k < 2) throw Error("local cubic fit: ring must be >= 2 (a cubic needs 5 samples per axis), got " + std::to_string(k));
  const int side = 2 * k + 1;
  if (volume.nx < side || volume.ny < side || volume.nz < side)
    throw Error("local cubic fit: volume of " + std::to_string(volume.nx) + "x" + std::to_string(volume.ny) + "x" +
                std::to_string(volume.nz) + " voxels is too small for ring " + std::to_string(k) + " (each dimension needs at least " +
                std::to_string(side) + ")");
  const Monomials monomials;
  const Eigen::MatrixXd fit = cubic_fit_operator(k);  // computed once for every voxel (Eq. 5.4 remark)
  const Eigen::MatrixXd fit_quadratic = fit.topRows(kNumQuadraticMonomials);

  LocalCubicFit result;
  result.nx = volume.nx;
  result.ny = volume.ny;
  result.nz = volume.nz;
  const std::size_t n = volume.num_voxels();
  result.value.resize(n);
  result.gradient.resize(n);
  result.hessian.resize(n);
  const Eigen::Vector3d inv_spacing = volume.spacing.cwiseInverse();

  if (options.threads < 1) throw Error("local cubic fit: threads must be >= 1, got " + std::to_string(options.threads));
  // One z plane per work chunk, in blocks of planes between progress reports (which stay on
  // the calling thread).
  // Per-plane scratch vectors allocated once up front (not inside the worker).
  std::vector<Eigen::VectorXd> windows(static_cast<std::size_t>(volume.nz), Eigen::VectorXd(side * side * side));
  std::vector<Eigen::VectorXd> coefficient_vectors(static_cast<std::size_t>(volume.nz), Eigen::VectorXd(kNumCubicMonomials));
  auto fit_plane = [&](int z) {
    Eigen::VectorXd& window = windows[static_cast<std::size_t>(z)];
    Eigen::VectorXd& coefficients = coefficient_vectors[static_cast<std::size_t>(z)];
    const int cz = std::clamp(z, k, volume.nz - 1 - k);
    for (int y = 0; y < volume.ny; ++y) {
      const int cy = std::clamp(y, k, volume.ny - 1 - k);
      for (int x = 0; x < volume.nx; ++x) {
        const int cx = std::clamp(x, k, volume.nx - 1 - k);
        int w = 0;
        for (int dz = -k; dz <= k; ++dz)
          for (int dy = -k; dy <= k; ++dy) {
            const float* row = &volume.samples[volume.index(cx - k, cy + dy, cz + dz)];
            for (int dx = 0; dx < side; ++dx) window[w++] = row[dx];
          }
        const std::size_t id = volume.index(x, y, z);
        double value = 0.0;
        Eigen::Vector3d gradient;
        Eigen::Matrix3d hessian;
        if (x == cx && y == cy && z == cz) {
          // At the window centre only the monomials of degree <= 2 contribute.
          coefficients.head(kNumQuadraticMonomials).noalias() = fit_quadratic * window;
          coefficients.tail(kNumCubicMonomials - kNumQuadraticMonomials).setZero();
        } else {
          coefficients.noalias() = fit * window;
        }
        evaluate(monomials, coefficients, Eigen::Vector3d(x - cx, y - cy, z - cz), value, gradient, hessian);
        result.value[id] = value;
        result.gradient[id] = gradient.cwiseProduct(inv_spacing);
        result.hessian[id] = inv_spacing.asDiagonal() * hessian * inv_spacing.asDiagonal();
      }
    }
  };
  constexpr int kPlanesPerReport = 16;
  for (int z0 = 0; z0 < volume.nz; z0 += kPlanesPerReport) {
    progress.report("local cubic fit", static_cast<double>(z0) / volume.nz);
    const int planes = std::min(kPlanesPerReport, volume.nz - z0);
    linalg::parallel_for(options.threads, planes, [&](int p) { fit_plane(z0 + p); });
  }
  progress.report("local cubic fit", 1.0);
  return result;
}

}  // namespace volspline::volume
