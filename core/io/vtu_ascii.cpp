// SPDX-License-Identifier: MIT
#include "core/io/vtu_ascii.h"

#include <cstdio>

namespace volspline::io {

void append_vtu_number(std::string& out, double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", x);
  out += buffer;
}

void append_vtu_triple(std::string& out, double x, double y, double z) {
  append_vtu_number(out, x);
  out += ' ';
  append_vtu_number(out, y);
  out += ' ';
  append_vtu_number(out, z);
  out += '\n';
}

std::string vtu_header(std::size_t points, std::size_t cells) {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" + std::to_string(points) + "\" NumberOfCells=\"" +
         std::to_string(cells) + "\">\n";
}

void append_vtu_scalars(std::string& out, const std::string& name, const std::vector<double>& values) {
  out += "<DataArray type=\"Float64\" Name=\"" + name + "\" format=\"ascii\">\n";
  for (double x : values) {
    append_vtu_number(out, x);
    out += '\n';
  }
  out += "</DataArray>\n";
}

}  // namespace volspline::io
