// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace volspline::polycube {

/// Face f (0..5) of the unit cube, or of a cuboid's parameter box, lies on the plane
/// (axis f / 2) = (f % 2): f = 2a is the low side of axis a, f = 2a + 1 the high side.

/// 2D coordinates (s, t) of a point of cube face f: the two in-plane coordinates of uvw,
/// axes (f/2 + 1) % 3 and (f/2 + 2) % 3. Orientation: triangles seen from outside are
/// counter-clockwise in (s, t) on the faces with f % 2 == 1 and clockwise on the others.
Eigen::Vector2d cube_face_coordinates(int face, const Eigen::Vector3d& uvw);

/// Inverse of cube_face_coordinates: the point (s, t) of face f as uvw in [0, 1]³.
Eigen::Vector3d cube_face_point(int face, double s, double t);

/// A set of the 6 faces of a cuboid (bit f for face f). A single-patch spline (one cuboid) has
/// all six exposed; in a generalized poly-cube a face glued to a neighbouring cuboid is not.
class CubeFaceSet {
 public:
  constexpr CubeFaceSet() = default;  ///< the empty set
  /// All six faces.
  static constexpr CubeFaceSet all() { return CubeFaceSet(0x3f); }
  /// True iff face f (0..5) is in the set.
  constexpr bool contains(int face) const { return (bits_ >> face) & 1u; }
  /// The set with face f (0..5) added.
  constexpr CubeFaceSet with(int face) const { return CubeFaceSet(bits_ | (1u << face)); }
  /// The set with face f (0..5) removed.
  constexpr CubeFaceSet without(int face) const { return CubeFaceSet(bits_ & ~(1u << face) & 0x3fu); }
  constexpr bool empty() const { return bits_ == 0; }
  constexpr bool operator==(CubeFaceSet other) const { return bits_ == other.bits_; }
  constexpr bool operator!=(CubeFaceSet other) const { return bits_ != other.bits_; }

 private:
  explicit constexpr CubeFaceSet(unsigned bits) : bits_(static_cast<std::uint8_t>(bits)) {}
  std::uint8_t bits_ = 0;
};

}  // namespace volspline::polycube
