// SPDX-License-Identifier: MIT
#include "core/spline/gpc_boundary_tessellation.h"

#include <cassert>
#include <utility>

#include "core/spline/boundary_tessellation.h"

namespace volspline::spline {

GpcBoundaryTessellation tessellate_gpc_boundary(const GpcSpline& spline, int samples, int lines) {
  assert(spline.dimension() == 3 && samples >= 2 && lines >= 2);
  BoundaryTessellation all;
  GpcBoundaryTessellation out;
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
      append_face_tessellation(face, samples, lines, evaluate, all);
      out.surface_cuboid.resize(all.surface_xyz.size() / 3, static_cast<std::uint32_t>(c));
      out.line_cuboid.resize(all.line_xyz.size() / 6, static_cast<std::uint32_t>(c));
    }
  }
  out.surface_xyz = std::move(all.surface_xyz);
  out.surface_uvw = std::move(all.surface_uvw);
  out.surface_triangles = std::move(all.surface_triangles);
  out.line_xyz = std::move(all.line_xyz);
  out.line_uvw = std::move(all.line_uvw);
  return out;
}

}  // namespace volspline::spline
