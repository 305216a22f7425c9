// SPDX-License-Identifier: MIT
#include "core/volume/hessian_frames.h"

#include <cmath>

#include <Eigen/Geometry>
#include <doctest/doctest.h>

#include "core/volume/local_cubic_fit.h"

using namespace volspline::volume;

TEST_CASE("hessian_frames: eigenvectors sorted by |eigenvalue| with canonical signs and det +1") {
  Eigen::Vector3d lambda;
  const Eigen::Matrix3d frame = principal_frame(Eigen::Vector3d(1, -3, 2).asDiagonal(), &lambda);
  CHECK((lambda - Eigen::Vector3d(-3, 2, 1)).norm() < 1e-12);
  Eigen::Matrix3d expected;
  expected << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  CHECK((frame - expected).norm() < 1e-12);
  // Equal magnitudes: the positive eigenvalue comes first.
  principal_frame(Eigen::Vector3d(-2, 2, 0.5).asDiagonal(), &lambda);
  CHECK((lambda - Eigen::Vector3d(2, -2, 0.5)).norm() < 1e-12);
  // A rotated tensor: rows are eigenvectors, the frame is a rotation, and T = F^T diag(lambda) F.
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d t = r * Eigen::Vector3d(5, -1, 0.25).asDiagonal() * r.transpose();
  const Eigen::Matrix3d f = principal_frame(t, &lambda);
  CHECK((f * f.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-12);
  CHECK(f.determinant() == doctest::Approx(1.0).epsilon(1e-12));
  CHECK((f.transpose() * lambda.asDiagonal() * f - t).norm() < 1e-12);
  CHECK(std::abs(std::abs(f.row(0).dot(r.col(0))) - 1) < 1e-12);
  const auto frames = hessian_frames({t, t});
  CHECK(frames.size() == 2);
  CHECK(frames[0] == f);
  CHECK(frames[1] == f);
}

TEST_CASE("hessian_frames: a Gaussian blob's fitted Hessian has a radial and two tangential directions") {
  // f = 1000 exp(-|p - c|^2 / (2 s^2)): H = f / s^2 (r r^T / s^2 - I), so r is an eigenvector
  // with eigenvalue f/s^2 (|r|^2/s^2 - 1) and the tangential eigenvalue -f/s^2 is double.
  const int n = 17;
  const double s = 4.0;
  const Eigen::Vector3d c(8, 8, 8);
  Volume v;
  v.nx = v.ny = v.nz = n;
  v.samples.resize(v.num_voxels());
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        v.samples[v.index(x, y, z)] = static_cast<float>(1000 * std::exp(-(Eigen::Vector3d(x, y, z) - c).squaredNorm() / (2 * s * s)));
  const LocalCubicFit fit = fit_local_cubics(v);
  const auto frames = hessian_frames(fit.hessian);
  int checked = 0;
  for (int z = 2; z < n - 2; ++z)
    for (int y = 2; y < n - 2; ++y)
      for (int x = 2; x < n - 2; ++x) {
        const Eigen::Vector3d r = Eigen::Vector3d(x, y, z) - c;
        if (r.norm() < 2.0 || r.norm() > 6.0) continue;
        Eigen::Vector3d lambda;
        const Eigen::Matrix3d f = principal_frame(fit.hessian[v.index(x, y, z)], &lambda);
        CHECK(f == frames[v.index(x, y, z)]);
        // The simple eigenvalue is the one farthest from the mean of the other two.
        int simple = 0;
        double gap = -1;
        for (int a = 0; a < 3; ++a) {
          const double other = (lambda.sum() - lambda[a]) / 2;
          if (std::abs(lambda[a] - other) > gap) {
            gap = std::abs(lambda[a] - other);
            simple = a;
          }
        }
        // A cubic over a 5^3 window only approximates a Gaussian: allow ~8 degrees.
        CHECK(std::abs(f.row(simple).dot(r.normalized())) > 0.99);
        ++checked;
      }
  CHECK(checked > 500);
}
