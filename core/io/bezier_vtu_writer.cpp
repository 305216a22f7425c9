// SPDX-License-Identifier: MIT
#include "core/io/bezier_vtu_writer.h"

#include <array>
#include <cassert>
#include <cstdint>

#include "core/io/file_bytes.h"
#include "core/io/vtk_xml_writer.h"
#include "core/spline/bezier_extraction.h"
#include "core/spline/jacobian_certificate.h"

namespace volspline::io {

int vtk_bezier_hex_index(int i, int j, int k) {
  constexpr int p = 3;  // degree per axis; m = p − 1 interior points per edge
  constexpr int m = p - 1;
  const bool bi = i == 0 || i == p, bj = j == 0 || j == p, bk = k == 0 || k == p;
  const int on = int(bi) + int(bj) + int(bk);
  // Corner c: bottom face (k = 0) counter-clockwise from (0,0), then the top face the same way.
  if (on == 3) return (i ? (j ? 2 : 1) : (j ? 3 : 0)) + (k ? 4 : 0);
  if (on == 2) {
    // Edges 0..3 bottom (u at v=0, v at u=p, u at v=p, v at u=0), 4..7 the same on top, then
    // the w edges at (u, v) = (0, 0), (p, 0), (0, p), (p, p): VTK 9.1 (Debian 12's, checked by
    // evaluating its cells) orders these by (u, v) bits, not as its corners 0, 1, 2, 3.
    if (!bi) return 8 + (i - 1) + (j ? 2 * m : 0) + (k ? 4 * m : 0);
    if (!bj) return 8 + (j - 1) + (i ? m : 3 * m) + (k ? 4 * m : 0);
    return 8 + 8 * m + (k - 1) + m * ((i ? 1 : 0) + (j ? 2 : 0));
  }
  const int faces = 8 + 12 * m;
  if (on == 1) {
    if (bi) return faces + (j - 1) + m * (k - 1) + (i ? m * m : 0);
    if (bj) return faces + 2 * m * m + (i - 1) + m * (k - 1) + (j ? m * m : 0);
    return faces + 4 * m * m + (i - 1) + m * (j - 1) + (k ? m * m : 0);
  }
  return faces + 6 * m * m + (i - 1) + m * ((j - 1) + m * (k - 1));
}

std::string serialize_bezier_vtu(const spline::TSpline& spline, const BezierVtuOptions& options,
                                 const std::vector<double>* cell_scaled_jacobian_min) {
  const int dim = spline.dimension();
  assert(dim == 3 || dim == 4);
  const int nc[3] = {int(spline.knot_lines(0).size()) - 1, int(spline.knot_lines(1).size()) - 1,
                     int(spline.knot_lines(2).size()) - 1};
  const int np[3] = {3 * nc[0] + 1, 3 * nc[1] + 1, 3 * nc[2] + 1};
  const std::size_t num_points = std::size_t(np[0]) * np[1] * np[2];
  const int num_cells = spline.num_cells();
  const bool rational = options.form == spline::TSplineForm::Rational;
  std::vector<double> xyz(num_points * 3), density(dim == 4 ? num_points : 0), weights(rational ? num_points : 0);
  std::vector<std::int64_t> connectivity(std::size_t(num_cells) * 64), offsets(num_cells);
  std::vector<std::uint8_t> types(num_cells, 79);  // VTK_BEZIER_HEXAHEDRON
  std::vector<std::int32_t> degrees(std::size_t(num_cells) * 3, 3), cuboid(num_cells, options.cuboid);
  for (int c = 0; c < num_cells; ++c) {
    const spline::BezierCell cell = spline::extract_bezier_cell(spline, c);
    const std::array<int, 3> k = spline.cell_index(c);
    for (int n = 0; n < 64; ++n) {
      const int i = n % 4, j = (n / 4) % 4, l = n / 16;
      const std::size_t id = std::size_t(3 * k[0] + i) + np[0] * (std::size_t(3 * k[1] + j) + np[1] * std::size_t(3 * k[2] + l));
      // Rational form: the homogeneous net (w p, w) gives control points (w p)/w and weights w.
      const double w = rational ? cell.weights[n] : 1.0;
      for (int d = 0; d < 3; ++d) xyz[id * 3 + d] = cell.points[n * dim + d] / w;
      if (dim == 4) density[id] = cell.points[n * dim + 3] / w;
      if (rational) weights[id] = w;
      connectivity[std::size_t(c) * 64 + vtk_bezier_hex_index(i, j, l)] = std::int64_t(id);
    }
    offsets[c] = std::int64_t(c + 1) * 64;
  }
  VtkXmlWriter writer(options.compress);
  std::string body = "<Piece NumberOfPoints=\"" + std::to_string(num_points) + "\" NumberOfCells=\"" +
                     std::to_string(num_cells) + "\">\n";
  body += "<PointData>\n";
  if (dim == 4) body += writer.add("density", density);
  if (rational) body += writer.add("RationalWeights", weights);
  body += "</PointData>\n<CellData>\n";
  body += writer.add("HigherOrderDegrees", degrees, 3);
  body += writer.add("cuboid", cuboid);
  if (dim == 3) {
    std::vector<double> bound;
    if (cell_scaled_jacobian_min) {
      bound = *cell_scaled_jacobian_min;
    } else {
      bound = spline::certify_jacobian(spline).cell_bound_rel;
    }
    assert(int(bound.size()) == num_cells);
    body += writer.add("scaled_jacobian_min", bound);
  }
  body += "</CellData>\n<Points>\n" + writer.add("Points", xyz, 3) + "</Points>\n<Cells>\n";
  body += writer.add("connectivity", connectivity);
  body += writer.add("offsets", offsets);
  body += writer.add("types", types);
  body += "</Cells>\n</Piece>\n";
  return writer.document("UnstructuredGrid", "", body);
}

void write_bezier_vtu(const std::string& path, const spline::TSpline& spline, const BezierVtuOptions& options) {
  write_file_atomic(path, serialize_bezier_vtu(spline, options));
}

}  // namespace volspline::io
