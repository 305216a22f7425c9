// SPDX-License-Identifier: MIT
#include "core/io/vtu_writer.h"

#include <cassert>
#include <vector>

#include "core/io/file_bytes.h"
#include "core/io/vtu_ascii.h"
#include "core/mesh/hex_quality.h"

namespace volspline::io {

namespace {

void append_vectors(std::string& out, const std::vector<Eigen::Vector3d>& vectors) {
  for (const auto& p : vectors) append_vtu_triple(out, p.x(), p.y(), p.z());
}

}  // namespace

std::string serialize_spline_vtu(const spline::TSpline& spline, const std::array<int, 3>& cells) {
  assert(spline.dimension() == 3 && cells[0] >= 1 && cells[1] >= 1 && cells[2] >= 1);
  const std::array<int, 3> n = {cells[0] + 1, cells[1] + 1, cells[2] + 1};
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  const int num_points = n[0] * n[1] * n[2];
  const int num_cells = cells[0] * cells[1] * cells[2];
  std::vector<Eigen::Vector3d> xyz(num_points), uvw(num_points);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const int id = i + n[0] * (j + n[1] * k);
        uvw[id] = lo + Eigen::Vector3d(double(i) / cells[0], double(j) / cells[1], double(k) / cells[2])
                           .cwiseProduct(hi - lo);
        xyz[id] = spline.evaluate(uvw[id]);
      }
  std::string out = vtu_header(num_points, num_cells);
  out += "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  append_vectors(out, xyz);
  out += "</DataArray>\n</Points>\n";
  out += "<PointData>\n<DataArray type=\"Float64\" Name=\"uvw\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  append_vectors(out, uvw);
  out += "</DataArray>\n</PointData>\n";
  std::string connectivity, offsets, types, quality;
  // VTK_HEXAHEDRON corner order: bottom face counter-clockwise, then top face.
  const int order[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  int offset = 0;
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i) {
        std::array<int, 8> corner;
        std::array<Eigen::Vector3d, 8> x;
        for (int c = 0; c < 8; ++c) {
          corner[c] = (i + (c & 1)) + n[0] * ((j + ((c >> 1) & 1)) + n[1] * (k + ((c >> 2) & 1)));
          x[c] = xyz[corner[c]];
        }
        for (int c = 0; c < 8; ++c) {
          connectivity += std::to_string(corner[order[c]]);
          connectivity += c < 7 ? ' ' : '\n';
        }
        offset += 8;
        offsets += std::to_string(offset) + '\n';
        types += "12\n";
        append_vtu_number(quality, mesh::hex_min_scaled_jacobian(x));
        quality += '\n';
      }
  out += "<CellData Scalars=\"scaled_jacobian\">\n<DataArray type=\"Float64\" Name=\"scaled_jacobian\" format=\"ascii\">\n";
  out += quality;
  out += "</DataArray>\n</CellData>\n<Cells>\n";
  out += "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n" + connectivity + "</DataArray>\n";
  out += "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n" + offsets + "</DataArray>\n";
  out += "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n" + types + "</DataArray>\n";
  out += "</Cells>\n";
  out += kVtuFooter;
  return out;
}

void write_spline_vtu(const std::string& path, const spline::TSpline& spline,
                      const std::array<int, 3>& cells) {
  write_file_atomic(path, serialize_spline_vtu(spline, cells));
}

}  // namespace volspline::io
