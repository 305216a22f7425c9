// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

namespace volspline::mesh {

/// n×3 vertex positions, row-major so that data() is the flat xyzxyz... array the browser reads.
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// m×3 vertex ids of triangles (counter-clockwise seen from outside), row-major.
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Indexed triangle mesh: the plain interchange struct between io, stages and bindings.
struct TriangleMesh {
  Positions positions;  ///< n×3, model units
  Triangles triangles;  ///< m×3, 0-based vertex ids

  int num_vertices() const { return static_cast<int>(positions.rows()); }
  int num_faces() const { return static_cast<int>(triangles.rows()); }
};

}  // namespace volspline::mesh
