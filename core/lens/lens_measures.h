// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/mesh/triangle_mesh.h"

namespace volspline::lens {

/// Shape distortion of a deformed triangle mesh (Eq. 6.9, measured alike for every lens method).
struct ShapeDistortion {
  double sum = 0;             ///< Σ over triangles of E_i
  double max = 0;             ///< max over triangles of E_i
  int flipped_triangles = 0;  ///< output triangles with non-positive signed area
  double sum_focus = 0;       ///< Σ of E_i over the focus triangles only (0 without a focus mask)
  double max_focus = 0;       ///< max of E_i over the focus triangles only
  int focus_triangles = 0;    ///< number of focus triangles
};

/// Per-triangle distortion E_i = Σ_j ‖e_j − M_i e_j^d‖² / Σ_j ‖e_j‖² (Eq. 6.9) with e^d the
/// texture-space (input image) edges, e the output edges and M_i their best similarity (Eq. 6.7).
/// Deviation: Eq. 6.9 weights with the lens-mesh w_ij and uses the method's own metric; neither
/// exists for fisheye/bifocal/zoom, so unit weights, the similarity fit and the normalization make
/// E_i ∈ [0, 1] comparable across methods (0: the triangle is only scaled and rotated).
/// output, texture: n×2 pixels; triangles: m×3. A degenerate or flipped output triangle scores 1.
ShapeDistortion measure_distortion(const Eigen::MatrixX2d& output, const Eigen::MatrixX2d& texture,
                                   const mesh::Triangles& triangles);

/// As above, and also over the focus region: `focus` has one flag per triangle (m entries),
/// non-zero for a triangle of the focus (e.g. its texture centroid inside a ROI).
ShapeDistortion measure_distortion(const Eigen::MatrixX2d& output, const Eigen::MatrixX2d& texture,
                                   const mesh::Triangles& triangles, const std::vector<char>& focus);

/// Triangles (all of them, grid and ROI-adapted) that the output turns over relative to the
/// texture: signed output area ≤ 0 where the texture area is > 0, or ≥ 0 where it is < 0. This is
/// the count a viewer of the exported mesh (positions textured with texture) sees flipped.
/// output, texture: n×2 pixels; triangles: m×3.
int count_flipped_triangles(const Eigen::MatrixX2d& output, const Eigen::MatrixX2d& texture,
                            const mesh::Triangles& triangles);

/// Linear magnification around `centre` (texture space, pixels): sqrt(Σ output area / Σ texture
/// area) over the triangles whose texture centroid lies within `radius` pixels of the centre
/// (the nearest triangle if none does). Returns 0 if the selected texture area is zero.
double measure_magnification(const Eigen::MatrixX2d& output, const Eigen::MatrixX2d& texture,
                             const mesh::Triangles& triangles, const Eigen::Vector2d& centre, double radius);

/// Mean over triangle edges of |ℓ_output / ℓ_3D − 1|: how well edge lengths of the 3D lens mesh survive.
double edge_length_error(const mesh::Positions& xyz, const Eigen::MatrixX2d& output, const mesh::Triangles& triangles);

/// Mean over triangle corners of |θ_output − θ_3D| in radians: how well angles of the 3D lens mesh survive.
double angle_error(const mesh::Positions& xyz, const Eigen::MatrixX2d& output, const mesh::Triangles& triangles);

}  // namespace volspline::lens
