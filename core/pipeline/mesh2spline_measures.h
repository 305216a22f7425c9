// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/halfedge_mesh.h"
#include "core/spline/hierarchical_refinement.h"
#include "core/spline/tspline.h"

namespace volspline::pipeline {

/// Distance from x to the spline's boundary surface near the boundary parameter uvw, model
/// units: Gauss–Newton on the two in-face parameters (clamped to the face), at most 6 steps from
/// uvw, each accepted only if it brings F closer to x. An upper bound of the distance to the
/// whole boundary surface, exact when the projection lands at the nearest surface point.
/// Precondition: spline has D = 3 and domain [0,1]³; some coordinate of uvw is 0 or 1 (the last
/// such axis selects the face). Throws like TSpline::evaluate_to if uvw is outside [0,1]³.
double surface_projection_distance(const spline::TSpline& spline, Eigen::Vector3d uvw, const Eigen::Vector3d& x);

/// The n Gauss–Legendre nodes on [0, 1], increasing (n ≥ 1).
std::vector<double> gauss_legendre_nodes(int n);

/// Options of measure_mesh2spline; every field is checked on entry (volspline::Error).
struct Mesh2SplineMeasureOptions {
  int surface_samples = 48;           ///< lattice points per axis per cuboid face, [8, 512]
  /// Gauss–Legendre points per axis in every knot-line cell for the scaled Jacobian, [1, 8]. The
  /// untangler holds knot-interval nodes, boundary layers and lattice centres, never these, and
  /// they come as close to the boundary as 0.11 of a cell's width (3 points).
  int jacobian_gauss_points = 3;
  int semi_standard_samples = 100000; ///< random parameters for semi_standard_max_error, ≥ 1
  std::uint64_t seed = 1;             ///< seeds those random parameters
};

/// The spline-quality measures of DESIGN.md for one cuboid.
struct Mesh2SplineMeasureResult {
  double hausdorff_rel = 0;             ///< two-sided spline boundary ↔ mesh distance / diagonal
  double rms_geo_rel = 0;               ///< RMS of the lattice and vertex distances / diagonal
  double min_scaled_jacobian = 1;       ///< at the Gauss points of every knot-line cell
  double negative_jacobian_fraction = 0;///< fraction of those points with scaled Jacobian <= 0
  long jacobian_samples = 0;            ///< number of those points
  double semi_standard_max_error = 0;   ///< max |Σ w_i B_i − 1| at the random parameters
};

/// Measures of a fitted spline F over [0,1]³ against the closed mesh it was fitted to.
/// - Spline → mesh: F at a surface_samples² lattice on each cube face, and at the 3×3 corner,
///   edge-midpoint and centre parameters of every boundary face of every refined leaf of
///   `refinement` (the lattice is coarse where the surface map is compressed), each to the
///   nearest mesh triangle.
/// - Mesh → spline: per vertex, the smaller of its distance to the lattice triangles and
///   surface_projection_distance from its own surface parameter vertex_uvw.
/// hausdorff_rel is the largest of all these, rms_geo_rel the RMS over the lattice points and
/// vertices; both divided by `diagonal` (model units, > 0). Scaled Jacobian det J /
/// (|J_u||J_v||J_w|) (−1 where a column vanishes) at the jacobian_gauss_points³ Gauss points of
/// every knot-line cell (interior points: along the cuboid's edges any map onto a smooth surface
/// is degenerate).
/// Inputs: spline with D = 3 and domain [0,1]³; mesh with at least one face; vertex_uvw n×3
/// (one row per mesh vertex, on the boundary of [0,1]³ for vertices with a halfedge).
/// Throws volspline::Error on bad options.
Mesh2SplineMeasureResult measure_mesh2spline(const spline::TSpline& spline, const mesh::HalfedgeMesh& mesh,
                                        const mesh::Positions& vertex_uvw,
                                        const spline::RefinementGrid& refinement, double diagonal,
                                        const Mesh2SplineMeasureOptions& options);

}  // namespace volspline::pipeline
