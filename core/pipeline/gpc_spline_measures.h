// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"
#include "core/spline/gpc_spline.h"

namespace volspline::pipeline {

/// Options of measure_gpc_spline; checked on entry (volspline::Error).
struct GpcSplineMeasureOptions {
  int surface_samples = 48;            ///< lattice points per axis per surface face, [8, 512]
  int jacobian_gauss_points = 3;       ///< Gauss–Legendre points per axis per knot cell, [1, 8]
  int lattice = 64;                    ///< cell centres per axis per cuboid, [4, 256]
  int interface_samples = 33;          ///< points per axis per glued face, [2, 512]
  int semi_standard_samples = 100000;  ///< random (cuboid, uvw) for semi_standard_max_error, ≥ 1
  std::uint64_t seed = 1;
};

/// A point of the solid's surface with its parameter: cuboid and local uvw (on a Surface face).
struct GpcSurfacePoint {
  int cuboid = -1;
  Eigen::Vector3d uvw = Eigen::Vector3d::Zero();
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();  ///< model units
};

/// Distance from a surface point to the spline's boundary near its own parameter: per surface
/// face holding the parameter (two on a cube edge, three at a corner), Gauss–Newton on the face's
/// two parameters (clamped to it), at most 8 steps, each kept only if it brings F closer; the
/// least over those faces. An upper bound of the distance to the boundary surface, in the units
/// of p.xyz and the spline's points.
double gpc_surface_point_distance(const spline::GpcSpline& spline, const GpcSurfacePoint& p);

/// DESIGN.md's spline measures over a GPC spline (D = 3).
struct GpcSplineMeasures {
  double hausdorff_rel = 0;   ///< two-sided spline boundary ↔ mesh distance / diagonal (upper bound)
  double rms_geo_rel = 0;     ///< RMS of those distances / diagonal
  double min_scaled_jacobian = 1;         ///< at the Gauss points of every knot cell of every cuboid
  double negative_jacobian_fraction = 0;  ///< fraction of those points with scaled Jacobian ≤ 0
  long jacobian_samples = 0;
  double lattice_negative_fraction = 0;   ///< the same at the lattice³ cell centres of every cuboid
  long lattice_samples = 0;
  double semi_standard_max_error = 0;     ///< max |Σ B_i − 1| at random parameters of all cuboids
  double interface_gap_rel = 0;           ///< max |F_a(x) − F_b(T x)| on glued faces / diagonal
  double interface_normal_jump_deg = 0;   ///< max angle of ∂F/∂n across Continued faces
};

/// Measures of `spline` against the closed `mesh` it was fitted to, `diagonal` its bbox
/// diagonal (model units, > 0).
/// - Spline → mesh: F at a surface_samples² lattice of cell centres on every Surface face of
///   every cuboid, each to the nearest mesh triangle. Mesh → spline: per surface point, the least |F − x|
///   after Gauss–Newton from its own parameter on each Surface face holding it (two on a cube
///   edge; at most 8 steps, clamped to the face): an upper bound of its distance to the boundary.
///   hausdorff_rel is the largest of these, rms_geo_rel their RMS, over `diagonal`.
/// - Scaled Jacobian det J / (|J_u||J_v||J_w|) at the Gauss points of every knot cell and at the
///   lattice cell centres; neither set is one the fit or an untangler holds.
/// - interface_gap_rel: on every glued face, F of both sides at interface_samples² points (the
///   second side's point through the transition, Eq. 3.4). interface_normal_jump_deg: at the same
///   points of the Continued faces, the angle between J_a·n and J_b·R·n (R: the transition's
///   rotation, so both are the derivative along the same direction).
/// Throws volspline::Error on bad options or a spline with D ≠ 3.
GpcSplineMeasures measure_gpc_spline(const spline::GpcSpline& spline, const mesh::TriangleMesh& mesh,
                                     const std::vector<GpcSurfacePoint>& surface_points, double diagonal,
                                     const GpcSplineMeasureOptions& options = {});

}  // namespace volspline::pipeline
