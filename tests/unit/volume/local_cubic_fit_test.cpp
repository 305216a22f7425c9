// SPDX-License-Identifier: MIT
#include "core/volume/local_cubic_fit.h"

#include <cmath>

#include <doctest/doctest.h>

#include "core/common/error.h"

using namespace volspline::volume;

namespace {

// f = 1 + 2x - y + 3z + x^2 - 2xy + yz - z^2/2 + x^3/4 - x y z / 2 + y^2 z / 4 - z^3 / 8 with
// its exact gradient and Hessian. At the sample points used below every value is a multiple of
// 1/64 well under 2^16, so the float samples hold it exactly.
double cubic(const Eigen::Vector3d& p) {
  const double x = p.x(), y = p.y(), z = p.z();
  return 1 + 2 * x - y + 3 * z + x * x - 2 * x * y + y * z - z * z / 2 + x * x * x / 4 - x * y * z / 2 + y * y * z / 4 -
         z * z * z / 8;
}
Eigen::Vector3d cubic_gradient(const Eigen::Vector3d& p) {
  const double x = p.x(), y = p.y(), z = p.z();
  return {2 + 2 * x - 2 * y + 3 * x * x / 4 - y * z / 2, -1 - 2 * x + z - x * z / 2 + y * z / 2,
          3 + y - z - x * y / 2 + y * y / 4 - 3 * z * z / 8};
}
Eigen::Matrix3d cubic_hessian(const Eigen::Vector3d& p) {
  const double x = p.x(), y = p.y(), z = p.z();
  Eigen::Matrix3d h;
  h << 2 + 1.5 * x, -2 - z / 2, -y / 2,  //
      -2 - z / 2, z / 2, 1 - x / 2 + y / 2,  //
      -y / 2, 1 - x / 2 + y / 2, -1 - 3 * z / 4;
  return h;
}

Volume sample(int nx, int ny, int nz, const Eigen::Vector3d& spacing, double (*f)(const Eigen::Vector3d&)) {
  Volume v;
  v.nx = nx;
  v.ny = ny;
  v.nz = nz;
  v.spacing = spacing;
  v.samples.resize(v.num_voxels());
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        v.samples[v.index(x, y, z)] = static_cast<float>(f(Eigen::Vector3d(x, y, z).cwiseProduct(spacing)));
  return v;
}

}  // namespace

TEST_CASE("local_cubic_fit: the operator is a left inverse of the fitting matrix (Eq. 5.4)") {
  for (int ring : {2, 3}) {
    const Eigen::MatrixXd op = cubic_fit_operator(ring);
    CHECK(op.rows() == kNumCubicMonomials);
    CHECK(op.cols() == (2 * ring + 1) * (2 * ring + 1) * (2 * ring + 1));
    // Fitting the window samples of the monomial 1 gives coefficient vector e_0.
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(op.cols());
    Eigen::VectorXd expected = Eigen::VectorXd::Zero(kNumCubicMonomials);
    expected[0] = 1;
    CHECK((op * ones - expected).norm() < 1e-12);  // exact identity up to rounding
  }
}

TEST_CASE("local_cubic_fit: reproduces a cubic's value, gradient and Hessian at every voxel, borders included") {
  for (const Eigen::Vector3d& spacing : {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(0.5, 1, 2)}) {
    const Volume v = sample(7, 6, 8, spacing, cubic);
    for (int ring : {2, 3}) {
      if (2 * ring + 1 > 6) continue;
      const LocalCubicFit fit = fit_local_cubics(v, {ring});
      double worst = 0.0;
      for (int z = 0; z < v.nz; ++z)
        for (int y = 0; y < v.ny; ++y)
          for (int x = 0; x < v.nx; ++x) {
            const Eigen::Vector3d p = Eigen::Vector3d(x, y, z).cwiseProduct(spacing);
            const std::size_t id = v.index(x, y, z);
            worst = std::max(worst, std::abs(fit.value[id] - cubic(p)));
            worst = std::max(worst, (fit.gradient[id] - cubic_gradient(p)).cwiseAbs().maxCoeff());
            worst = std::max(worst, (fit.hessian[id] - cubic_hessian(p)).cwiseAbs().maxCoeff());
          }
      // Exact data and an exact model: only rounding of a well-conditioned 20-column QR remains.
      CHECK(worst < 1e-9);
    }
  }
}

TEST_CASE("local_cubic_fit: rejects a ring below 2 and volumes smaller than the window") {
  const Volume v = sample(5, 5, 4, Eigen::Vector3d::Ones(), cubic);
  auto message = [&](int ring) {
    try {
      fit_local_cubics(v, {ring});
    } catch (const volspline::Error& e) {
      return std::string(e.what());
    }
    return std::string("<no error>");
  };
  CHECK(message(1) == "local cubic fit: ring must be >= 2 (a cubic needs 5 samples per axis), got 1");
  CHECK(message(2) == "local cubic fit: volume of 5x5x4 voxels is too small for ring 2 (each dimension needs at least 5)");
}
