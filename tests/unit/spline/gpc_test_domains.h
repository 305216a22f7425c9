// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>  // determinant

#include "core/polycube/gpc_domain.h"
#include "core/spline/gpc_spline.h"

namespace volspline::test {

// The box [0, size] of cuboid c as a vector.
inline Eigen::Vector3d cuboid_size(const polycube::GpcDomain& d, int c) {
  return {d.cuboids[c].size[0], d.cuboids[c].size[1], d.cuboids[c].size[2]};
}

// A cuboid placed in a global frame: local coordinates h ∈ [0, size] map to placement.apply(h)
// (a rotation by multiples of π/2 and a translation, as a polycube::GpcTransition).
struct PlacedCuboid {
  std::array<double, 3> size{1.0, 1.0, 1.0};
  polycube::GpcTransition placement;
};

// The 24 proper rotations of the cube as signed axis permutations.
inline std::vector<polycube::GpcTransition> cube_rotations() {
  std::vector<polycube::GpcTransition> out;
  const std::array<std::array<int, 3>, 6> perms = {{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (const auto& p : perms)
    for (int s = 0; s < 8; ++s) {
      polycube::GpcTransition t;
      Eigen::Matrix3d r = Eigen::Matrix3d::Zero();
      for (int i = 0; i < 3; ++i) {
        t.axis[i] = p[i];
        t.sign[i] = (s >> i) & 1 ? -1 : 1;
        r(p[i], i) = t.sign[i];
      }
      if (r.determinant() > 0.0) out.push_back(t);
    }
  return out;
}

// A cuboid of global extent [lo, lo + extent] whose local axes are rotated by `rotation`
// (a translation-free GpcTransition): sizes and translation follow.
inline PlacedCuboid place_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& extent,
                              const polycube::GpcTransition& rotation) {
  PlacedCuboid out;
  out.placement = rotation;
  for (int i = 0; i < 3; ++i) out.size[i] = extent(rotation.axis[i]);
  out.placement.translation = Eigen::Vector3d::Zero();
  // The image of the local box starts where its lowest corner lands.
  Eigen::Vector3d image_lo = Eigen::Vector3d::Constant(1e300);
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d h((c & 1) * out.size[0], ((c >> 1) & 1) * out.size[1], ((c >> 2) & 1) * out.size[2]);
    image_lo = image_lo.cwiseMin(out.placement.apply(h));
  }
  out.placement.translation = lo - image_lo;
  return out;
}

// The GPC of boxes in a global frame: every pair of faces that coincide with opposite normals is
// glued, with the transition placement_b⁻¹ ∘ placement_a (Eq. 3.4).
inline polycube::GpcDomain glue_boxes(const std::vector<PlacedCuboid>& boxes) {
  polycube::GpcDomain domain;
  struct GlobalFace {
    int axis, normal;
    double plane;
    Eigen::Vector3d lo, hi;
  };
  auto face_of = [&](int c, int f) {
    const PlacedCuboid& b = boxes[c];
    GlobalFace g;
    g.axis = b.placement.axis[f / 2];
    g.normal = b.placement.sign[f / 2] * (f % 2 == 0 ? -1 : 1);
    g.lo = Eigen::Vector3d::Constant(1e300);
    g.hi = Eigen::Vector3d::Constant(-1e300);
    for (int k = 0; k < 8; ++k) {
      Eigen::Vector3d h((k & 1) * b.size[0], ((k >> 1) & 1) * b.size[1], ((k >> 2) & 1) * b.size[2]);
      h(f / 2) = (f % 2) * b.size[f / 2];
      const Eigen::Vector3d x = b.placement.apply(h);
      g.lo = g.lo.cwiseMin(x);
      g.hi = g.hi.cwiseMax(x);
    }
    g.plane = g.lo(g.axis);
    return g;
  };
  const int n = static_cast<int>(boxes.size());
  domain.cuboids.resize(n);
  for (int c = 0; c < n; ++c) {
    domain.cuboids[c].size = boxes[c].size;
    for (int k = 0; k < 8; ++k)
      domain.cuboids[c].corner_xyz[k] = boxes[c].placement.apply(Eigen::Vector3d(
          (k & 1) * boxes[c].size[0], ((k >> 1) & 1) * boxes[c].size[1], ((k >> 2) & 1) * boxes[c].size[2]));
  }
  for (int c = 0; c < n; ++c)
    for (int f = 0; f < 6; ++f)
      for (int d = c + 1; d < n; ++d)
        for (int g = 0; g < 6; ++g) {
          const GlobalFace a = face_of(c, f), b = face_of(d, g);
          if (a.axis != b.axis || a.normal != -b.normal || std::abs(a.plane - b.plane) > 1e-12) continue;
          if ((a.lo - b.lo).norm() > 1e-12 || (a.hi - b.hi).norm() > 1e-12) continue;
          polycube::GpcInterface in;
          in.cuboid = {c, d};
          in.face = {f, g};
          in.transition = boxes[d].placement.inverse().after(boxes[c].placement);
          domain.cuboids[c].face_interface[f] = static_cast<int>(domain.interfaces.size());
          domain.cuboids[d].face_interface[g] = static_cast<int>(domain.interfaces.size());
          domain.interfaces.push_back(in);
        }
  return domain;
}

// Two cuboids glued face to face, the second's local frame rotated by π/2 about the glued
// normal: A = [0,1]×[0,0.8]×[0,0.6] (placement identity), B of global extent
// [1,2.3]×[0,0.8]×[0,0.6] with local u, v, w along global x, z, −y: sizes (1.3, 0.6, 0.8).
inline std::vector<PlacedCuboid> two_cube_boxes() {
  polycube::GpcTransition identity, quarter;
  quarter.axis = {0, 2, 1};
  quarter.sign = {1, 1, -1};
  return {place_box({0.0, 0.0, 0.0}, {1.0, 0.8, 0.6}, identity),
          place_box({1.0, 0.0, 0.0}, {1.3, 0.8, 0.6}, quarter)};
}

// A T made of a centre cube Z with three arms (L to −x, R to +x, D to −y), and a fifth cube L2
// beyond L: Type-1 ill-points along the concave edges Z∩L∩D and Z∩R∩D. Frames rotated.
// Cuboid ids: Z 0, L 1, L2 2, R 3, D 4.
inline std::vector<PlacedCuboid> t_shape_boxes() {
  const std::vector<polycube::GpcTransition> rot = cube_rotations();
  return {place_box({0, 0, 0}, {1, 1, 1}, rot[0]), place_box({-1, 0, 0}, {1, 1, 1}, rot[5]),
          place_box({-2, 0, 0}, {1, 1, 1}, rot[11]), place_box({1, 0, 0}, {1, 1, 1}, rot[17]),
          place_box({0, -1, 0}, {1, 1, 1}, rot[22])};
}

inline polycube::GpcDomain t_shape_domain() {
  polycube::GpcDomain d = glue_boxes(t_shape_boxes());
  polycube::GpcIllPoint a, b;
  a.cuboids = {0, 1, 4};
  b.cuboids = {0, 3, 4};
  d.ill_points = {a, b};
  d.t_shapes = 1;
  return d;
}

// nx×ny×nz boxes of unequal widths, each with a random local frame (seeded): every edge inside
// is regular (4 cuboids), every inside vertex has 8.
inline std::vector<PlacedCuboid> block_boxes(const std::array<std::vector<double>, 3>& widths, unsigned seed) {
  const std::vector<polycube::GpcTransition> rot = cube_rotations();
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(rot.size()) - 1);
  std::vector<PlacedCuboid> out;
  double z = 0.0;
  for (double wz : widths[2]) {
    double y = 0.0;
    for (double wy : widths[1]) {
      double x = 0.0;
      for (double wx : widths[0]) {
        out.push_back(place_box({x, y, z}, {wx, wy, wz}, rot[pick(rng)]));
        x += wx;
      }
      y += wy;
    }
    z += wz;
  }
  return out;
}

// One cuboid [0,1]×[0,s]×[0,s'] glued to itself: face u = 0 to face u = 1 (a closed tube, the
// solid torus of a genus-1 GPC). With `twist` the gluing also turns the cross-section by π/2
// (then s = s' = 0.3).
inline polycube::GpcDomain torus_domain(bool twist) {
  polycube::GpcDomain d;
  d.cuboids.resize(1);
  d.cuboids[0].size = {1.0, 0.3, twist ? 0.3 : 0.2};
  polycube::GpcInterface in;
  in.cuboid = {0, 0};
  in.face = {0, 1};
  in.transition.translation = Eigen::Vector3d(1.0, 0.0, 0.0);
  if (twist) {
    in.transition.axis = {0, 2, 1};
    in.transition.sign = {1, 1, -1};
    in.transition.translation = Eigen::Vector3d(1.0, 0.3, 0.0);
  }
  d.interfaces.push_back(in);
  d.cuboids[0].face_interface[0] = d.cuboids[0].face_interface[1] = 0;
  d.genus = 1;
  d.tubes = 1;
  return d;
}

// Control points at the placed anchors, mirrored in x if `mirror`: F is each cuboid's placement
// (a rotation: scaled Jacobian 1) or its mirror image (−1), exactly (Greville abscissae
// reproduce linear maps).
inline void place_at_anchors(spline::GpcSpline& spline, const std::vector<PlacedCuboid>& boxes, bool mirror = false) {
  Eigen::MatrixXd p(spline.num_functions(), 3);
  for (int i = 0; i < spline.num_functions(); ++i) {
    const spline::GpcAnchor& anchor = spline.anchor(i);
    p.row(i) = boxes[anchor.cuboid].placement.apply(anchor.uvw).transpose();
    if (mirror) p(i, 0) = -p(i, 0);
  }
  spline.set_points(p);
}

// A GPC spline over glue_boxes(boxes) with the given knot intervals per cuboid and its control
// points at the placed anchors: F is each cuboid's placement, exactly.
inline spline::GpcSpline placed_gpc_spline(const std::vector<PlacedCuboid>& boxes,
                                           const std::vector<std::array<int, 3>>& intervals) {
  spline::GpcSplineOptions o;
  o.intervals = intervals;
  spline::GpcSpline spline(glue_boxes(boxes), o);
  place_at_anchors(spline, boxes);
  return spline;
}

/// Splits, for ℓ = 0 .. levels − 1 in turn, the level-ℓ function largest at (cuboid, uvw) (a
/// chain of splits down to level `levels` at one point); false if a level had no function there.
inline bool split_down_at(spline::GpcSpline& spline, int cuboid, const Eigen::Vector3d& uvw, int levels) {
  std::vector<int> ids;
  std::vector<double> values;
  for (int level = 0; level < levels; ++level) {
    spline.basis_at(cuboid, uvw, {0, 0, 0}, ids, values);
    int largest = -1;
    for (std::size_t k = 0; k < ids.size(); ++k)
      if (spline.function_level(ids[k]) == level && (largest < 0 || values[k] > values[largest]))
        largest = static_cast<int>(k);
    if (largest < 0) return false;
    spline = spline.refined({ids[largest]});
  }
  return true;
}

}  // namespace volspline::test
