// SPDX-License-Identifier: MIT
#include "core/spline/gpc_spline_cut.h"

#include <algorithm>
#include <cassert>

#include "core/mesh/hex_quality.h"
#include "core/polycube/cube_faces.h"
#include "core/spline/boundary_tessellation.h"

namespace volspline::spline {

GpcSplineCut gpc_spline_cut(const GpcSpline& spline, int axis, double t, int samples) {
  assert(spline.dimension() == 3 && axis >= 0 && axis < 3 && t >= 0 && t <= 1 && samples >= 2);
  GpcSplineCut out;
  const int m = samples;
  double value[3], jacobian[9];
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    const auto& box = spline.domain().cuboids[c].size;
    const Eigen::Vector3d size(box[0], box[1], box[2]);
    const auto base = static_cast<std::uint32_t>(out.xyz.size() / 3);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        // The low face of the axis moved to t, in cuboid c's own coordinates (§3.5).
        Eigen::Vector3d unit = polycube::cube_face_point(2 * axis, double(i) / (m - 1), double(j) / (m - 1));
        unit(axis) = t;
        spline.evaluate_with_jacobian(c, unit.cwiseProduct(size), value, jacobian);
        for (int d = 0; d < 3; ++d) out.xyz.push_back(static_cast<float>(value[d]));
        const Eigen::Map<const Eigen::Matrix3d> J(jacobian);  // column a = ∂F/∂uvw_a
        const auto q = static_cast<float>(mesh::scaled_jacobian(J));
        out.scaled_jacobian.push_back(q);
        out.min_scaled_jacobian = std::min(out.min_scaled_jacobian, q);
        out.cuboid.push_back(static_cast<std::uint32_t>(c));
        for (int d = 0; d < 3; ++d) out.uvw.push_back(static_cast<float>(unit[d] * size[d]));
      }
    append_lattice_triangles(out.triangles, base, m, false);
  }
  return out;
}

}  // namespace volspline::spline
