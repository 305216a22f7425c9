// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/spline/bspline_multipatch.h"

namespace volspline::io {

/// MFEM NURBS mesh (`MFEM NURBS mesh v1.0`, the `patches` form): the patch topology (one hex
/// element per patch, corners in MFEM's order (0,0,0) (1,0,0) (1,1,0) (0,1,0) then the same at
/// w = 1; boundary quads with attribute 1; every edge once with the id of its knot vector class
/// and its end vertices in that class's direction), then per patch its three knot vectors
/// (order 3, control point count, knots), dimension D and `controlpoints` (x y z w, w = 1: the
/// patches are polynomial). Knot vector classes join the tangent axes of glued sides, whose knots
/// the multipatch makes equal. Precondition: spline::multipatch_topology_is_vertex_based (MFEM
/// identifies edges and faces by their vertices). Numbers at round-trip precision.
std::string serialize_mfem_mesh(const spline::BsplineMultipatch& multipatch);

}  // namespace volspline::io
