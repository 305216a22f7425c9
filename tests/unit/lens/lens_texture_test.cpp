// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/lens/lens_mesh.h"
#include "core/lens/lens_texture.h"
#include "tests/unit/common/test_lenses.h"

using namespace volspline::lens;

namespace {
LensMesh lens_mesh(double h0) {
  return volspline::test::circle_lens_mesh("circle:50,45,22", 100, 90, h0, 30);
}
}  // namespace

TEST_CASE("flat lens: mean-value weights reproduce linear functions, so the texture is the identity") {
  const LensMesh m = lens_mesh(0.0);
  const Eigen::MatrixX2d uv = harmonic_texture(m);
  // Linear precision of mean-value coordinates; 1e-6 px is far above the solver's 1e-9 relative residual.
  CHECK((uv - m.xyz.leftCols<2>()).cwiseAbs().maxCoeff() < 1e-6);
}

TEST_CASE("raised lens: only ROI vertices move, inwards, and stay inside the ROI") {
  const LensMesh m = lens_mesh(1.0);
  const Eigen::MatrixX2d uv = harmonic_texture(m);
  int moved = 0;
  for (int v = 0; v < m.xyz.rows(); ++v) {
    const Eigen::Vector2d p = m.xyz.row(v).head<2>().transpose(), t = uv.row(v).transpose();
    if (!m.in_roi[v]) {
      CHECK(t == p);  // Dirichlet outside the ROIs (§6.3.2)
      continue;
    }
    const Eigen::Vector2d c(50, 45);
    CHECK((t - c).norm() < 22.0);
    // The texture of the raised top is compressed towards the centre (that is the magnification).
    if ((p - c).norm() > 3.0 && (p - c).norm() < 19.0) moved += (t - c).norm() < (p - c).norm();
  }
  CHECK(moved > 20);
}
