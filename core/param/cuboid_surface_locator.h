// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/halfedge_mesh.h"
#include "core/param/cuboid_surface_map.h"

namespace volspline::param {

/// Inverse of a cuboid surface map (thesis §3.4.2 step (1)): the surface point xyz of a cube
/// surface parameter, by point location in the parameter triangles of the cube face and
/// barycentric interpolation of the vertex positions. Owns copies of what it needs.
class CuboidSurfaceLocator {
 public:
  /// Builds one uniform bucket grid per cube face over its parameter triangles, O(F).
  /// Preconditions: `map` was computed for `mesh` and is bijective.
  CuboidSurfaceLocator(const mesh::HalfedgeMesh& mesh, const CuboidSurfaceMap& map);

  /// Surface point of (s, t) ∈ [0,1]² on cube face f (see cube_face_coordinates), model units.
  /// Parameters are clamped to the square; points on shared poly-edges agree between faces
  /// up to rounding.
  Eigen::Vector3d locate(int face, double s, double t) const;

  /// Surface point of uvw on the boundary of [0,1]³ (the face is the first coordinate at 0 or 1,
  /// axes in order u, v, w). Precondition: some coordinate is 0 or 1.
  Eigen::Vector3d locate_uvw(const Eigen::Vector3d& uvw) const;

 private:
  struct FaceIndex {
    int resolution = 1;
    std::vector<int> bucket_begin;  // resolution² + 1 offsets into triangles
    std::vector<int> triangles;     // mesh face ids
  };
  mesh::Positions positions_;
  mesh::Triangles triangles_;
  std::vector<Eigen::Vector2d> corner_st_;  // 3 per mesh face, in its cube face
  std::array<FaceIndex, 6> faces_;
};

}  // namespace volspline::param
