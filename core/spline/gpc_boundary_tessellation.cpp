// SPDX-License-Identifier: MIT
#include "core/spline/gpc_boundary_tessellation.h"

#include <cassert>

#include "core/spline/boundary_tessellation.h"

namespace volspline::spline {

namespace {

void append_point(std::vector<float>& out, const Eigen::Vector3d& p) {
  for (int d = 0; d < 3; ++d) out.push_back(static_cast<float>(p(d)));
}

}  // namespace

GpcBoundaryTessellation tessellate_gpc_boundary(const GpcSpline& spline, int samples, int lines) {
  assert(spline.dimension() == 3 && samples >= 2 && lines >= 2);
  GpcBoundaryTessellation out;
  const int m = samples;
  double value[3], jacobian[9];
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    const auto& box = spline.domain().cuboids[c].size;
    const Eigen::Vector3d size(box[0], box[1], box[2]);
    auto evaluate = [&](const Eigen::Vector3d& unit) {
      spline.evaluate_with_jacobian(c, unit.cwiseProduct(size), value, jacobian);
      return Eigen::Vector3d(value[0], value[1], value[2]);
    };
    // The solid's boundary is the cuboids' Surface faces (§3.5); a glued face lies inside it.
    const polycube::CubeFaceSet faces = spline.exposed_faces(c);
    for (int face = 0; face < 6; ++face) {
      if (!faces.contains(face)) continue;
      const auto base = static_cast<std::uint32_t>(out.surface_xyz.size() / 3);
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i) {
          const Eigen::Vector3d unit = polycube::cube_face_point(face, double(i) / (m - 1), double(j) / (m - 1));
          append_point(out.surface_xyz, evaluate(unit));
          append_point(out.surface_uvw, unit);
          out.surface_cuboid.push_back(static_cast<std::uint32_t>(c));
        }
      // Outward orientation: (s, t) is counter-clockwise seen from outside on odd faces.
      append_lattice_triangles(out.surface_triangles, base, m, face % 2 == 0);
      const int steps = 4 * (m - 1);
      for (int dir = 0; dir < 2; ++dir)
        for (int l = 0; l < lines; ++l) {
          const double fixed = double(l) / (lines - 1);
          Eigen::Vector3d previous = Eigen::Vector3d::Zero(), previous_unit = Eigen::Vector3d::Zero();
          for (int q = 0; q <= steps; ++q) {
            const double moving = double(q) / steps;
            const Eigen::Vector3d unit = dir == 0 ? polycube::cube_face_point(face, fixed, moving)
                                                  : polycube::cube_face_point(face, moving, fixed);
            const Eigen::Vector3d p = evaluate(unit);
            if (q > 0) {
              append_point(out.line_xyz, previous);
              append_point(out.line_xyz, p);
              append_point(out.line_uvw, previous_unit);
              append_point(out.line_uvw, unit);
              out.line_cuboid.push_back(static_cast<std::uint32_t>(c));
            }
            previous = p;
            previous_unit = unit;
          }
        }
    }
  }
  return out;
}

}  // namespace volspline::spline
