// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

namespace volspline::polycube {

/// A transition map between the local coordinates of two cuboids (§3.5, Eq. 3.4): a rotation by
/// multiples of π/2 and a translation, h_b[axis[i]] = sign[i]·h_a[i] + translation[axis[i]].
/// Local coordinates of a cuboid run over [0, size[0]]×[0, size[1]]×[0, size[2]].
struct GpcTransition {
  std::array<int, 3> axis{0, 1, 2};
  std::array<int, 3> sign{1, 1, 1};
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d apply(const Eigen::Vector3d& h) const {
    Eigen::Vector3d out;
    for (int i = 0; i < 3; ++i) out(axis[i]) = sign[i] * h(i) + translation(axis[i]);
    return out;
  }
  /// The map the other way round.
  GpcTransition inverse() const {
    GpcTransition inv;
    for (int i = 0; i < 3; ++i) {
      inv.axis[axis[i]] = i;
      inv.sign[axis[i]] = sign[i];
    }
    for (int j = 0; j < 3; ++j) inv.translation(inv.axis[j]) = -inv.sign[j] * translation(j);
    return inv;
  }
  /// this ∘ first: first applied, then this.
  GpcTransition after(const GpcTransition& first) const {
    GpcTransition out;
    for (int i = 0; i < 3; ++i) {
      out.axis[i] = axis[first.axis[i]];
      out.sign[i] = sign[first.axis[i]] * first.sign[i];
    }
    out.translation = apply(first.translation);
    return out;
  }
};

/// One cuboid of a generalized poly-cube (§3.2).
struct GpcCuboid {
  std::array<double, 3> size{1.0, 1.0, 1.0};  ///< domain lengths along u, v, w (bbox diagonals)
  std::array<int, 3> nodes{2, 2, 2};          ///< volumetric grid nodes per axis (§3.4.2)
  int piece = -1;                             ///< decomposition piece it belongs to
  int piece_kind = 0;                         ///< that piece's boundary loop count (0..3)
  /// Per cube face (f: plane axis f/2 at f%2): the interface glued there, −1 if it is on the
  /// surface of the solid.
  std::array<int, 6> face_interface{-1, -1, -1, -1, -1, -1};
  std::array<Eigen::Vector3d, 8> corner_xyz{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};  ///< model units, corner c at (c&1, c>>1&1, c>>2&1)
};

/// Two cuboid faces glued together (a GPC-graph edge, §3.2).
struct GpcInterface {
  std::array<int, 2> cuboid{-1, -1};
  std::array<int, 2> face{-1, -1};
  GpcTransition transition;  ///< local coordinates of cuboid[0] → those of cuboid[1]
  int cut = -1;              ///< the cut loop it spans, −1 for a face inside a T-shape
};

/// A Type-1 ill-point (Fig. 3.1(e)): a concave edge of the domain where three cuboids meet
/// around a reflex angle (in 3D a segment of Type-1 points), inside a T-shape.
struct GpcIllPoint {
  int type = 1;
  std::array<int, 3> cuboids{-1, -1, -1};
  std::array<Eigen::Vector3d, 2> xyz{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};  ///< its end points on the surface, model units
};

/// The GPC graph: cuboids, glued faces with their transition maps, ill-points.
struct GpcDomain {
  std::vector<GpcCuboid> cuboids;
  std::vector<GpcInterface> interfaces;
  std::vector<GpcIllPoint> ill_points;
  int genus = 0;
  int caps = 0;
  int tubes = 0;
  int t_shapes = 0;
};

/// The transition that glues face fa of a cuboid with sizes sa to face fb of one with sizes sb,
/// where the corners ca[i] of the first (cube corner ids, 0..7, on face fa) meet cb[i] of the
/// second. The first cuboid's interior maps outside the second. Returns false if the corners do
/// not describe a rotation (mirrored or not on the faces).
bool gpc_transition_from_corners(int fa, const std::array<double, 3>& sa, const std::array<int, 4>& ca, int fb,
                                 const std::array<double, 3>& sb, const std::array<int, 4>& cb,
                                 GpcTransition& out);

}  // namespace volspline::polycube
