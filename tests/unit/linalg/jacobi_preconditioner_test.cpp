// SPDX-License-Identifier: MIT
#include "core/linalg/jacobi_preconditioner.h"

#include <doctest/doctest.h>

namespace linalg = volspline::linalg;

TEST_CASE("Jacobi inverts the diagonal and replaces zeros by one") {
  const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(
      3, 3, {{0, 0, 4.0}, {0, 1, 1.0}, {1, 0, 1.0}, {2, 2, -0.5}});
  linalg::JacobiPreconditioner m;
  m.compute(a);
  CHECK(m.inverse_diagonal() == Eigen::Vector3d(0.25, 1.0, -2.0));
  const Eigen::VectorXd z = m.solve(Eigen::VectorXd(Eigen::Vector3d(1.0, 2.0, 3.0)));
  CHECK(z == Eigen::VectorXd(Eigen::Vector3d(0.25, 2.0, -6.0)));
  Eigen::VectorXd in_place = Eigen::Vector3d(1.0, 2.0, 3.0);
  m.solve(in_place.data(), in_place.data());
  CHECK(in_place == z);
}
