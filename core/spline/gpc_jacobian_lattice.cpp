// SPDX-License-Identifier: MIT
#include "core/spline/gpc_jacobian_lattice.h"

#include <algorithm>
#include <cassert>

#include "core/mesh/hex_quality.h"

namespace volspline::spline {

GpcJacobianLattice sample_gpc_jacobian_lattice(const GpcSpline& spline, int n) {
  assert(spline.dimension() == 3 && n >= 1);
  GpcJacobianLattice out;
  const std::size_t count = static_cast<std::size_t>(spline.num_cuboids()) * n * n * n;
  out.scaled_jacobian.reserve(count);
  out.xyz.reserve(3 * count);
  double value[3], jacobian[9];
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    const auto& box = spline.domain().cuboids[c].size;
    // Each cuboid in its own local coordinates (§3.5).
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Eigen::Vector3d uvw(box[0] * (i + 0.5) / n, box[1] * (j + 0.5) / n, box[2] * (k + 0.5) / n);
          spline.evaluate_with_jacobian(c, uvw, value, jacobian);
          const auto q = static_cast<float>(mesh::scaled_jacobian(Eigen::Map<const Eigen::Matrix3d>(jacobian)));
          out.scaled_jacobian.push_back(q);
          out.min_scaled_jacobian = std::min(out.min_scaled_jacobian, q);
          for (int d = 0; d < 3; ++d) out.xyz.push_back(static_cast<float>(value[d]));
        }
  }
  return out;
}

}  // namespace volspline::spline
