// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

#include "core/spline/gpc_spline.h"
#include "core/spline/tspline.h"

namespace volspline::io {

/// Index of net point (i, j, k) (i along u, each in 0..3) of a cubic Bézier hexahedron in VTK's
/// point order for VTK_BEZIER_HEXAHEDRON (vtkHigherOrderHexahedron): the 8 corners (bottom face
/// counter-clockwise, then top), the interior points of the 12 edges (each along its axis; the
/// four w edges in (u, v) bit order as VTK 9.1 reads them), of
/// the 6 faces (u-normal pair, v-normal pair, w-normal pair, lower first), then the interior.
int vtk_bezier_hex_index(int i, int j, int k);

/// Options of serialize_bezier_vtu.
struct BezierVtuOptions {
  spline::TSplineForm form = spline::TSplineForm::SemiStandard;  ///< Rational: RationalWeights written
  bool compress = true;  ///< zlib, where the build has it (VtkXmlWriter)
  int cuboid = 0;        ///< value of the `cuboid` cell data
};

/// A spline with D = 3 (geometry) or D = 4 (geometry + density) as VTK XML UnstructuredGrid of
/// VTK_BEZIER_HEXAHEDRON cells (type 79), one per knot-line cell, each its exact 4×4×4 Bernstein
/// net (spline::extract_bezier_cell), so VTK draws and evaluates the spline itself. Points lie on
/// the global Bézier lattice (3·cells + 1 per axis): neighbouring cells share their face nets.
/// Cell data: `HigherOrderDegrees` (3, 3, 3), `cuboid`, `uvw_min` and `uvw_max` (the cell's
/// parameter box: VTK's parametric (r, s, t) maps to uvw_min + (r, s, t) ⊙ (uvw_max − uvw_min)),
/// `scaled_jacobian_min` (the certified
/// lower bound of the scaled Jacobian, spline::certify_jacobian; negative where not certified,
/// and then a fold indicator, not a bound;
/// D = 3 only). Point data: `density` (D = 4) and, in the rational form, `RationalWeights`. In the
/// semi-standard form (Eq. 4.3) F is polynomial on each cell and no weights are written. Appended
/// binary data, zlib-compressed where available. Precondition: D is 3 or 4.
std::string serialize_bezier_vtu(const spline::TSpline& spline, const BezierVtuOptions& options = {},
                                 const std::vector<double>* cell_scaled_jacobian_min = nullptr);

/// A geometric GPC spline (D = 3) the same way: the knot-line cells inside every cuboid's box
/// (its patch's cells beyond a Continued face are the neighbour's), each cuboid on its own
/// Bézier lattice (glued faces carry equal nets, not shared points), cell data `cuboid` and
/// `scaled_jacobian_min` from spline::certify_jacobian_in_box. options.cuboid is not used.
std::string serialize_gpc_bezier_vtu(const spline::GpcSpline& spline, const BezierVtuOptions& options = {});

/// Writes serialize_bezier_vtu atomically (the certificate is computed for D = 3). Throws
/// volspline::Error naming the path on failure.
void write_bezier_vtu(const std::string& path, const spline::TSpline& spline, const BezierVtuOptions& options = {});

}  // namespace volspline::io
