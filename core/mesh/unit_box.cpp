// SPDX-License-Identifier: MIT
#include "core/mesh/unit_box.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/error.h"

namespace volspline::mesh {

namespace {

// Smallest box side, relative to the largest coordinate magnitude, that still holds a shape.
constexpr double kMinSideRel = 1e-12;

}  // namespace

Eigen::Vector3d UnitBox::to_unit(const Eigen::Vector3d& xyz) const {
  Eigen::Vector3d unit;
  for (int a = 0; a < 3; ++a) unit(a) = (xyz(a) - centre(a)) / side;
  return unit;
}

Eigen::Vector3d UnitBox::from_unit(const Eigen::Vector3d& unit) const {
  Eigen::Vector3d xyz;
  for (int a = 0; a < 3; ++a) xyz(a) = unit(a) * side + centre(a);
  return xyz;
}

TriangleMesh UnitBox::to_unit(const TriangleMesh& mesh) const {
  TriangleMesh unit = mesh;
  for (Eigen::Index v = 0; v < unit.positions.rows(); ++v)
    unit.positions.row(v) = to_unit(Eigen::Vector3d(mesh.positions.row(v).transpose())).transpose();
  return unit;
}

Eigen::MatrixXd UnitBox::from_unit_points(const Eigen::MatrixXd& points) const {
  Eigen::MatrixXd xyz = points;
  for (Eigen::Index i = 0; i < xyz.rows(); ++i)
    for (int a = 0; a < 3 && a < xyz.cols(); ++a) xyz(i, a) = points(i, a) * side + centre(a);
  return xyz;
}

UnitBox unit_box_of(const TriangleMesh& mesh, const std::string& name) {
  const std::string prefix = "mesh '" + name + "': ";
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(f, k);
      if (v < 0 || v >= mesh.num_vertices()) continue;  // the half-edge build names bad ids
      const Eigen::Vector3d p = mesh.positions.row(v).transpose();
      if (!p.allFinite()) throw Error(prefix + "vertex " + std::to_string(v) + " has a coordinate that is not finite");
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  UnitBox box;
  if (!(lo.array() <= hi.array()).all()) return box;  // no used vertex
  // (lo + hi) / 2 could overflow; lo + (hi - lo) / 2 is exact enough once hi - lo is finite.
  const Eigen::Vector3d side = hi - lo;
  if (!side.allFinite())
    throw Error(prefix + "the coordinates span more than the range of doubles; cannot normalize the model");
  box.centre = lo + 0.5 * side;
  const double longest = side.maxCoeff();
  const double magnitude = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  if (longest == 0.0) {
    box.centre.setZero();
    return box;
  }
  if (longest < kMinSideRel * magnitude)
    throw Error(prefix + "the model is " + std::to_string(longest) + " wide at a distance of " +
                std::to_string(magnitude) + " from the origin: its coordinates hold too few digits of the shape");
  box.side = longest;
  return box;
}

}  // namespace volspline::mesh
