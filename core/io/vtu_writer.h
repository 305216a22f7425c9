// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <string>

#include "core/spline/tspline.h"

namespace volspline::io {

/// Hex mesh of a geometric T-spline (dimension 3) as VTK XML UnstructuredGrid (.vtu, appended
/// binary, zlib-compressed where the build has zlib and `compress` is set; VtkXmlWriter):
/// nodes F(uvw) on a uniform (cells[0]+1)×(cells[1]+1)×(cells[2]+1) lattice of the domain,
/// VTK_HEXAHEDRON cells, CellData "scaled_jacobian" (smallest corner scaled Jacobian of each
/// hex, in [−1, 1]) and PointData "uvw". Asserts dimension 3 and cells ≥ 1.
std::string serialize_spline_vtu(const spline::TSpline& spline, const std::array<int, 3>& cells,
                                 bool compress = true);

/// Writes serialize_spline_vtu atomically. Throws volspline::Error naming the path on failure.
void write_spline_vtu(const std::string& path, const spline::TSpline& spline,
                      const std::array<int, 3>& cells);

}  // namespace volspline::io
