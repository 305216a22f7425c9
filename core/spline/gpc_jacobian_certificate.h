// SPDX-License-Identifier: MIT
#pragma once

#include "core/spline/gpc_spline.h"
#include "core/spline/jacobian_certificate.h"

namespace volspline::spline {

/// The certificate options of a GPC spline: 24 splits (1/256 of the cell per axis), which settle
/// cells where det J > 0 comes within about 1e-4 of the column bound of 0 (fertility has some
/// that 12 splits leave Undecided); the rounding allowance as JacobianCertificateOptions.
JacobianCertificateOptions gpc_certificate_options();

/// The det J certificate (certify_bezier_cell, DESIGN §6) of every knot-line cell inside every
/// cuboid's box of a geometric GPC spline (D = 3): each cuboid's patch is one TSpline whose cells
/// beyond the box (where a face is Continued) are the neighbour's, so they are skipped. cells,
/// certified_cells, jacobian_certified_fraction and det_j_lower_bound_rel cover all cuboids;
/// uncertified cells name their cuboid, their patch cell id and box in that cuboid's
/// coordinates; cell_bound_rel lists the in-box cells' bounds cuboid by cuboid in cell order.
/// cache (or null): cells unchanged since its last call take its results (the same certificate).
/// Throws volspline::Error if the dimension is not 3 or options are invalid.
JacobianCertificate certify_gpc_jacobian(const GpcSpline& spline, const JacobianCertificateOptions& options = gpc_certificate_options(),
                                         JacobianCertificateCache* cache = nullptr);

}  // namespace volspline::spline
