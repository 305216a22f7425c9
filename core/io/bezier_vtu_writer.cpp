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

namespace {

// One patch's cells inside a box, written with their cuboid id and certified bounds (one per
// in-box cell, in cell order).
struct BezierPart {
  const spline::TSpline* spline = nullptr;
  Eigen::Vector3d box_min, box_max;
  int cuboid = 0;
  const std::vector<double>* bounds = nullptr;
};

std::string serialize_parts(const std::vector<BezierPart>& parts, const BezierVtuOptions& options) {
  const int dim = parts.front().spline->dimension();
  assert(dim == 3 || dim == 4);
  const bool rational = options.form == spline::TSplineForm::Rational;
  std::vector<double> xyz, density, weights, bound, uvw_min, uvw_max;
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::int32_t> cuboid;
  std::size_t point_base = 0;
  for (const BezierPart& part : parts) {
    const spline::TSpline& spline = *part.spline;
    // The part's cells: grid intervals [first, last) per axis inside the box.
    int first[3], nc[3];
    for (int a = 0; a < 3; ++a) {
      const std::vector<double>& lines = spline.knot_lines(a);
      const double tol = 1e-9 * (part.box_max[a] - part.box_min[a]);
      int lo = 0, hi = int(lines.size()) - 1;
      while (lo < hi && lines[lo] < part.box_min[a] - tol) ++lo;
      while (hi > lo && lines[hi] > part.box_max[a] + tol) --hi;
      first[a] = lo;
      nc[a] = hi - lo;
    }
    const std::size_t np[3] = {std::size_t(3 * nc[0] + 1), std::size_t(3 * nc[1] + 1), std::size_t(3 * nc[2] + 1)};
    const std::size_t num_points = np[0] * np[1] * np[2];
    xyz.resize(xyz.size() + num_points * 3);
    if (dim == 4) density.resize(density.size() + num_points);
    if (rational) weights.resize(weights.size() + num_points);
    const int n0 = int(spline.knot_lines(0).size()) - 1, n1 = int(spline.knot_lines(1).size()) - 1;
    for (int k2 = 0; k2 < nc[2]; ++k2)
      for (int k1 = 0; k1 < nc[1]; ++k1)
        for (int k0 = 0; k0 < nc[0]; ++k0) {
          const int c = (first[0] + k0) + n0 * ((first[1] + k1) + n1 * (first[2] + k2));
          const spline::BezierCell cell = spline::extract_bezier_cell(spline, c);
          const std::size_t base = connectivity.size();
          connectivity.resize(base + 64);
          for (int n = 0; n < 64; ++n) {
            const int i = n % 4, j = (n / 4) % 4, l = n / 16;
            const std::size_t id = point_base + std::size_t(3 * k0 + i) +
                                   np[0] * (std::size_t(3 * k1 + j) + np[1] * std::size_t(3 * k2 + l));
            // Rational form: the homogeneous net (w p, w) gives control points (w p)/w and weights w.
            const double w = rational ? cell.weights[n] : 1.0;
            for (int d = 0; d < 3; ++d) xyz[id * 3 + d] = cell.points[n * dim + d] / w;
            if (dim == 4) density[id] = cell.points[n * dim + 3] / w;
            if (rational) weights[id] = w;
            connectivity[base + vtk_bezier_hex_index(i, j, l)] = std::int64_t(id);
          }
          offsets.push_back(std::int64_t(connectivity.size()));
          cuboid.push_back(part.cuboid);
          uvw_min.insert(uvw_min.end(), cell.uvw_min.data(), cell.uvw_min.data() + 3);
          uvw_max.insert(uvw_max.end(), cell.uvw_max.data(), cell.uvw_max.data() + 3);
        }
    if (dim == 3) {
      const std::vector<double> computed =
          part.bounds ? std::vector<double>() : spline::certify_jacobian_in_box(spline, part.box_min, part.box_max).cell_bound_rel;
      const std::vector<double>& b = part.bounds ? *part.bounds : computed;
      assert(b.size() == std::size_t(nc[0]) * nc[1] * nc[2]);
      bound.insert(bound.end(), b.begin(), b.end());
    }
    point_base += num_points;
  }
  const std::size_t num_cells = offsets.size();
  std::vector<std::uint8_t> types(num_cells, 79);  // VTK_BEZIER_HEXAHEDRON
  std::vector<std::int32_t> degrees(num_cells * 3, 3);
  VtkXmlWriter writer(options.compress);
  std::string body = "<Piece NumberOfPoints=\"" + std::to_string(point_base) + "\" NumberOfCells=\"" +
                     std::to_string(num_cells) + "\">\n";
  body += "<PointData>\n";
  if (dim == 4) body += writer.add("density", density);
  if (rational) body += writer.add("RationalWeights", weights);
  body += "</PointData>\n<CellData>\n";
  body += writer.add("HigherOrderDegrees", degrees, 3);
  body += writer.add("cuboid", cuboid);
  body += writer.add("uvw_min", uvw_min, 3);
  body += writer.add("uvw_max", uvw_max, 3);
  if (dim == 3) body += writer.add("scaled_jacobian_min", bound);
  body += "</CellData>\n<Points>\n" + writer.add("Points", xyz, 3) + "</Points>\n<Cells>\n";
  body += writer.add("connectivity", connectivity);
  body += writer.add("offsets", offsets);
  body += writer.add("types", types);
  body += "</Cells>\n</Piece>\n";
  return writer.document("UnstructuredGrid", "", body);
}

}  // namespace

std::string serialize_bezier_vtu(const spline::TSpline& spline, const BezierVtuOptions& options,
                                 const std::vector<double>* cell_scaled_jacobian_min) {
  return serialize_parts({{&spline, spline.domain_min(), spline.domain_max(), options.cuboid, cell_scaled_jacobian_min}},
                         options);
}

std::string serialize_gpc_bezier_vtu(const spline::GpcSpline& spline, const BezierVtuOptions& options) {
  std::vector<BezierPart> parts;
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    const auto& size = spline.domain().cuboids[c].size;
    parts.push_back({&spline.patch(c), Eigen::Vector3d::Zero(), Eigen::Vector3d(size[0], size[1], size[2]), c, nullptr});
  }
  return serialize_parts(parts, options);
}

void write_bezier_vtu(const std::string& path, const spline::TSpline& spline, const BezierVtuOptions& options) {
  write_file_atomic(path, serialize_bezier_vtu(spline, options));
}

}  // namespace volspline::io
