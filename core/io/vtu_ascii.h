// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace volspline::io {

/// The pieces of an ASCII VTK XML UnstructuredGrid (.vtu) that every writer shares. Numbers are
/// written with 9 significant digits: a .vtu is a sampled view, not a round-trip format.

/// Appends x as "%.9g".
void append_vtu_number(std::string& out, double x);

/// Appends "x y z\n".
void append_vtu_triple(std::string& out, double x, double y, double z);

/// The XML declaration, <VTKFile>, <UnstructuredGrid> and the opening <Piece> of one piece with
/// `points` points and `cells` cells.
std::string vtu_header(std::size_t points, std::size_t cells);

/// Closes what vtu_header opened.
inline constexpr const char* kVtuFooter = "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";

/// Appends a Float64 DataArray named `name` with one value per line.
void append_vtu_scalars(std::string& out, const std::string& name, const std::vector<double>& values);

}  // namespace volspline::io
