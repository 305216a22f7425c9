// SPDX-License-Identifier: MIT
#include "core/io/vtu_writer.h"

#include <cassert>
#include <cstdint>
#include <vector>

#include "core/io/file_bytes.h"
#include "core/io/vtk_xml_writer.h"
#include "core/mesh/hex_quality.h"

namespace volspline::io {


std::string serialize_spline_vtu(const spline::TSpline& spline, const std::array<int, 3>& cells, bool compress) {
  assert(spline.dimension() == 3 && cells[0] >= 1 && cells[1] >= 1 && cells[2] >= 1);
  const std::array<int, 3> n = {cells[0] + 1, cells[1] + 1, cells[2] + 1};
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  const int num_points = n[0] * n[1] * n[2];
  const int num_cells = cells[0] * cells[1] * cells[2];
  std::vector<double> xyz(std::size_t(num_points) * 3), uvw(std::size_t(num_points) * 3);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t id = std::size_t(i) + n[0] * (std::size_t(j) + n[1] * std::size_t(k));
        const Eigen::Vector3d p =
            lo + Eigen::Vector3d(double(i) / cells[0], double(j) / cells[1], double(k) / cells[2]).cwiseProduct(hi - lo);
        spline.evaluate_to(p, spline::TSplineForm::SemiStandard, xyz.data() + 3 * id);
        for (int a = 0; a < 3; ++a) uvw[3 * id + a] = p[a];
      }
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types(num_cells, 12);  // VTK_HEXAHEDRON
  std::vector<double> quality;
  // VTK_HEXAHEDRON corner order: bottom face counter-clockwise, then top face.
  const int order[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i) {
        std::array<int, 8> corner;
        std::array<Eigen::Vector3d, 8> x;
        for (int c = 0; c < 8; ++c) {
          corner[c] = (i + (c & 1)) + n[0] * ((j + ((c >> 1) & 1)) + n[1] * (k + ((c >> 2) & 1)));
          x[c] = Eigen::Vector3d(xyz[3 * corner[c]], xyz[3 * corner[c] + 1], xyz[3 * corner[c] + 2]);
        }
        for (int c = 0; c < 8; ++c) connectivity.push_back(corner[order[c]]);
        offsets.push_back(std::int64_t(connectivity.size()));
        quality.push_back(mesh::hex_scaled_jacobian(x));
      }
  VtkXmlWriter writer(compress);
  std::string body = "<Piece NumberOfPoints=\"" + std::to_string(num_points) + "\" NumberOfCells=\"" +
                     std::to_string(num_cells) + "\">\n";
  body += "<PointData>\n" + writer.add("uvw", uvw, 3) + "</PointData>\n";
  body += "<CellData Scalars=\"scaled_jacobian\">\n" + writer.add("scaled_jacobian", quality) + "</CellData>\n";
  body += "<Points>\n" + writer.add("Points", xyz, 3) + "</Points>\n<Cells>\n";
  body += writer.add("connectivity", connectivity) + writer.add("offsets", offsets) + writer.add("types", types);
  body += "</Cells>\n</Piece>\n";
  return writer.document("UnstructuredGrid", "", body);
}

void write_spline_vtu(const std::string& path, const spline::TSpline& spline,
                      const std::array<int, 3>& cells) {
  write_file_atomic(path, serialize_spline_vtu(spline, cells));
}

}  // namespace volspline::io
