// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"

namespace volspline::mesh {

/// The map of a model into a unit box, so tolerances, solvers and measures never depend on
/// where the model sits or its units: unit = (xyz - centre) / side, the longest side becoming 1.
/// (A power-of-two scale would be exact but leaves a factor up to 2 between a model and its
/// scaled copy, and the stages' choices depend on that; one rounding per coordinate does not.)
struct UnitBox {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< bounding-box centre, model units
  double side = 1.0;                                 ///< longest bounding-box side, model units

  Eigen::Vector3d to_unit(const Eigen::Vector3d& xyz) const;
  Eigen::Vector3d from_unit(const Eigen::Vector3d& unit) const;
  /// The mesh with every vertex mapped by to_unit (triangles unchanged).
  TriangleMesh to_unit(const TriangleMesh& mesh) const;
  /// n×k points whose first 3 columns are unit coordinates, mapped back by from_unit (other
  /// columns, e.g. a density, unchanged).
  Eigen::MatrixXd from_unit_points(const Eigen::MatrixXd& points) const;
};

/// The unit box of the vertices that the mesh's triangles use (unused vertices do not count;
/// a mesh without them, or of zero size, gets the identity).
/// Throws volspline::Error naming `name` if a used coordinate is not finite, the box spans beyond
/// the double range (1e300-sized models can still be normalized; a span of 2e308 cannot), or the
/// box is smaller than 1e-12 of its distance from the origin (its coordinates then hold fewer
/// than 4 significant digits of the shape).
UnitBox unit_box_of(const TriangleMesh& mesh, const std::string& name);

}  // namespace volspline::mesh
