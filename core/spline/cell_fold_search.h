// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "core/spline/bezier_extraction.h"

namespace volspline::spline {

/// A point of a Bézier cell and det J there.
struct CellJacobianPoint {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();  ///< local coordinates in [0, 1]³
  double det_j = 0;                             ///< det ∂F/∂uvw at s
};

/// Searches for the point of a geometric Bézier cell (D = 3) where det ∂F/∂uvw is lowest: the
/// lowest of det J on the 5³ grid of s ∈ {0, ¼, ½, ¾, 1}³ and at `start` (e.g. the certificate's
/// lowest corner), then a compass search from there (the 26 neighbours at step h inside the
/// closed cell, h halved when none is lower, from ⅛ down to 1/1024). A local search, not a
/// bound: the certificate (certify_bezier_cell) proves where det J ≥ 0; this finds where an
/// uncertified cell folds, which its lowest box corner may miss (the fold can lie between the
/// corners of the boxes the subdivision visited). Deterministic. Precondition: cell.dimension ==
/// 3, start in [0, 1]³.
CellJacobianPoint lowest_jacobian_point(const BezierCell& cell, const Eigen::Vector3d& start);

}  // namespace volspline::spline
