// SPDX-License-Identifier: MIT
#include "core/volume/hessian_frames.h"

#include <algorithm>
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
  REQUIRE(frames.size() > 4096);  // several chunks of the threaded version
  CHECK(hessian_frames(fit.hessian, 3) == frames);  // exact: each frame depends on its tensor only
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

TEST_CASE("hessian_frames: a torus density's fitted frame is radial, toroidal and their cross product") {
  // f = 1000 exp(-d^2 / (2 s^2)), d = distance to the core circle (radius R in the z = c plane).
  // With phi(d) the profile, H = phi'' n n^T + phi' Hess(d): eigenvectors n (from the core
  // circle, eigenvalue phi''), the circle tangent t (phi' (rho - R) / (d rho)) and n x t (phi'/d).
  const int n = 24;
  const double s = 2.0, big_r = 6.5;
  const Eigen::Vector3d c(11.5, 11.5, 11.5);
  Volume v;
  v.nx = v.ny = v.nz = n;
  v.samples.resize(v.num_voxels());
  auto parts = [&](const Eigen::Vector3d& p, double& rho, double& d) {
    rho = std::hypot(p.x() - c.x(), p.y() - c.y());
    d = std::hypot(rho - big_r, p.z() - c.z());
  };
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        double rho = 0, d = 0;
        parts(Eigen::Vector3d(x, y, z), rho, d);
        v.samples[v.index(x, y, z)] = static_cast<float>(1000 * std::exp(-d * d / (2 * s * s)));
      }
  const LocalCubicFit fit = fit_local_cubics(v);
  const auto frames = hessian_frames(fit.hessian);
  REQUIRE(frames.size() > 4096);  // several chunks of the threaded version
  CHECK(hessian_frames(fit.hessian, 3) == frames);  // exact: each frame depends on its tensor only
  int checked = 0;
  double worst_cos = 1.0;
  for (int z = 2; z < n - 2; ++z)
    for (int y = 2; y < n - 2; ++y)
      for (int x = 2; x < n - 2; ++x) {
        const Eigen::Vector3d p(x, y, z);
        double rho = 0, d = 0;
        parts(p, rho, d);
        if (d < 1.0 || d > 3.5 || rho < 3.0) continue;
        // Analytic eigenvalues in units of phi / s^2; keep voxels where the three magnitudes are
        // apart by 30% of the largest (|l_3| = 1), so the fit's error cannot swap directions.
        const double l_n = d * d / (s * s) - 1, l_t = -(rho - big_r) / rho, l_3 = -1.0;
        const double a[3] = {std::abs(l_n), std::abs(l_t), std::abs(l_3)};
        const double largest = std::max({a[0], a[1], a[2]});
        bool separated = true;
        for (int i = 0; i < 3; ++i)
          for (int j = i + 1; j < 3; ++j) separated = separated && std::abs(a[i] - a[j]) > 0.3 * largest;
        if (!separated) continue;
        const Eigen::Vector3d radial_xy = Eigen::Vector3d(p.x() - c.x(), p.y() - c.y(), 0).normalized();
        const Eigen::Vector3d normal = (((rho - big_r) * radial_xy + Eigen::Vector3d(0, 0, p.z() - c.z())) / d).normalized();
        const Eigen::Vector3d tangent = Eigen::Vector3d::UnitZ().cross(radial_xy);
        const Eigen::Vector3d third = normal.cross(tangent);
        const Eigen::Matrix3d& f = frames[v.index(x, y, z)];
        double local = 1.0;
        for (const Eigen::Vector3d& e : {normal, tangent, third}) local = std::min(local, (f * e).cwiseAbs().maxCoeff());
        worst_cos = std::min(worst_cos, local);
        ++checked;
      }
  CHECK(checked > 100);
  // Every analytic direction within 12 degrees of a fitted axis (measured 7.8; the 5^3 cubic fit of a
  // Gaussian tube of width 2 voxels is approximate).
  CHECK(worst_cos > std::cos(12.0 * 3.14159265358979323846 / 180.0));
}
