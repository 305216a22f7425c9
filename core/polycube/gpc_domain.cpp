// SPDX-License-Identifier: MIT
#include "core/polycube/gpc_domain.h"

#include <cmath>

namespace volspline::polycube {

namespace {

Eigen::Vector3d corner_point(int c, const std::array<double, 3>& s) {
  return Eigen::Vector3d((c & 1) * s[0], ((c >> 1) & 1) * s[1], ((c >> 2) & 1) * s[2]);
}

// The unit axis direction of a vector along one axis: (axis, sign); false if not axis-aligned.
bool axis_of(const Eigen::Vector3d& d, int& axis, int& sign) {
  int count = 0;
  for (int a = 0; a < 3; ++a)
    if (d(a) != 0.0) {
      axis = a;
      sign = d(a) > 0.0 ? 1 : -1;
      ++count;
    }
  return count == 1;
}

}  // namespace

bool gpc_transition_from_corners(int fa, const std::array<double, 3>& sa, const std::array<int, 4>& ca, int fb,
                                 const std::array<double, 3>& sb, const std::array<int, 4>& cb,
                                 GpcTransition& out) {
  // Three directions of A and their images in B: two edges of the face and the inward normal,
  // which maps to B's outward normal.
  std::array<Eigen::Vector3d, 3> da, db;
  da[0] = corner_point(ca[1], sa) - corner_point(ca[0], sa);
  db[0] = corner_point(cb[1], sb) - corner_point(cb[0], sb);
  da[1] = corner_point(ca[3], sa) - corner_point(ca[0], sa);
  db[1] = corner_point(cb[3], sb) - corner_point(cb[0], sb);
  da[2] = Eigen::Vector3d::Unit(fa / 2) * (fa % 2 == 0 ? 1.0 : -1.0);
  db[2] = Eigen::Vector3d::Unit(fb / 2) * (fb % 2 == 0 ? -1.0 : 1.0);
  std::array<int, 3> seen{0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    int a, s_a, b, s_b;
    if (!axis_of(da[k], a, s_a) || !axis_of(db[k], b, s_b)) return false;
    out.axis[a] = b;
    out.sign[a] = s_a * s_b;
    ++seen[a];
  }
  if (seen[0] != 1 || seen[1] != 1 || seen[2] != 1) return false;
  // Proper rotation: the signed permutation has determinant +1.
  Eigen::Matrix3d r = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) r(out.axis[i], i) = out.sign[i];
  if (!(r.determinant() > 0.0)) return false;
  out.translation = Eigen::Vector3d::Zero();
  const Eigen::Vector3d image = out.apply(corner_point(ca[0], sa));
  out.translation = corner_point(cb[0], sb) - image;
  // Every corner must land on its partner.
  for (int i = 0; i < 4; ++i)
    if ((out.apply(corner_point(ca[i], sa)) - corner_point(cb[i], sb)).norm() > 1e-12) return false;
  return true;
}

}  // namespace volspline::polycube
