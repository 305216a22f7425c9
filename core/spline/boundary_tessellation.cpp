// SPDX-License-Identifier: MIT
#include "core/spline/boundary_tessellation.h"

#include <cassert>

namespace volspline::spline {

namespace {

void append_point(std::vector<float>& out, const Eigen::Vector3d& p) {
  for (int d = 0; d < 3; ++d) out.push_back(static_cast<float>(p(d)));
}

}  // namespace

void append_lattice_triangles(std::vector<std::uint32_t>& out, std::uint32_t base, int m, bool flip) {
  for (int j = 0; j + 1 < m; ++j)
    for (int i = 0; i + 1 < m; ++i) {
      const std::uint32_t a = base + i + m * j, b = a + 1, c = a + m + 1, d = a + m;
      const std::uint32_t tri[6] = {a, b, c, a, c, d};
      for (int k = 0; k < 6; k += 3) {
        out.push_back(tri[k]);
        out.push_back(flip ? tri[k + 2] : tri[k + 1]);
        out.push_back(flip ? tri[k + 1] : tri[k + 2]);
      }
    }
}

void append_face_tessellation(int face, int samples, int lines,
                              const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& evaluate,
                              BoundaryTessellation& out) {
  const int m = samples;
  const auto base = static_cast<std::uint32_t>(out.surface_xyz.size() / 3);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const Eigen::Vector3d unit = polycube::cube_face_point(face, double(i) / (m - 1), double(j) / (m - 1));
      append_point(out.surface_xyz, evaluate(unit));
      append_point(out.surface_uvw, unit);
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
        }
        previous = p;
        previous_unit = unit;
      }
    }
}

BoundaryTessellation tessellate_boundary(const TSpline& spline, int samples, int lines, polycube::CubeFaceSet faces) {
  assert(spline.dimension() == 3 && samples >= 2 && lines >= 2);
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  auto evaluate = [&](const Eigen::Vector3d& unit) -> Eigen::Vector3d {
    return spline.evaluate(lo + unit.cwiseProduct(hi - lo));
  };
  BoundaryTessellation out;
  for (int face = 0; face < 6; ++face)
    if (faces.contains(face)) append_face_tessellation(face, samples, lines, evaluate, out);
  return out;
}

}  // namespace volspline::spline
