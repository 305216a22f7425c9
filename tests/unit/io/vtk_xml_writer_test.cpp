// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "core/io/bezier_vtu_writer.h"
#include "core/io/vti_format.h"
#include "core/io/vtk_xml_writer.h"
#include "core/spline/bspline_volume.h"

using namespace volspline;

namespace {

// An ImageData file of nx×ny×nz samples, the array written by VtkXmlWriter.
std::string image(const std::vector<float>& samples, int nx, int ny, int nz, bool compress) {
  io::VtkXmlWriter writer(compress);
  const std::string extent = "0 " + std::to_string(nx - 1) + " 0 " + std::to_string(ny - 1) + " 0 " +
                             std::to_string(nz - 1);
  std::string body = "<Piece Extent=\"" + extent + "\">\n<PointData Scalars=\"density\">\n";
  body += writer.add("density", samples);
  body += "</PointData>\n<CellData>\n</CellData>\n</Piece>\n";
  return writer.document("ImageData", "WholeExtent=\"" + extent + "\" Origin=\"0 0 0\" Spacing=\"1 1 1\"", body);
}

}  // namespace

TEST_CASE("VTK XML appended arrays read back (compressed in several blocks and raw)") {
  const int nx = 40, ny = 30, nz = 9;  // 10,800 floats: 43 KB, two 32 KiB compression blocks
  std::vector<float> samples(size_t(nx) * ny * nz);
  for (size_t i = 0; i < samples.size(); ++i) samples[i] = float(i % 97) * 0.5f - 3.0f;
  for (bool compress : {true, false}) {
    CAPTURE(compress);
    const std::string text = image(samples, nx, ny, nz, compress);
    CHECK((text.find("vtkZLibDataCompressor") != std::string::npos) ==
          (compress && io::VtkXmlWriter::compression_available()));
    const volume::Volume v = io::parse_vti(text, "test.vti");
    REQUIRE(v.nx == nx);
    REQUIRE(v.ny == ny);
    REQUIRE(v.nz == nz);
    CHECK(v.samples == samples);
    CHECK(image(samples, nx, ny, nz, compress) == text);  // deterministic bytes
  }
}

TEST_CASE("VTK Bézier hexahedron point order is a permutation with the corners first") {
  std::set<int> seen;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) seen.insert(io::vtk_bezier_hex_index(i, j, k));
  CHECK(seen.size() == 64);
  CHECK(*seen.begin() == 0);
  CHECK(*seen.rbegin() == 63);
  CHECK(io::vtk_bezier_hex_index(0, 0, 0) == 0);
  CHECK(io::vtk_bezier_hex_index(3, 0, 0) == 1);
  CHECK(io::vtk_bezier_hex_index(3, 3, 0) == 2);
  CHECK(io::vtk_bezier_hex_index(0, 3, 0) == 3);
  CHECK(io::vtk_bezier_hex_index(0, 3, 3) == 7);
  CHECK(io::vtk_bezier_hex_index(1, 0, 0) == 8);   // first edge, along u
  CHECK(io::vtk_bezier_hex_index(1, 1, 1) == 56);  // interior, after 8 + 24 + 24
}

TEST_CASE("Bézier VTU: one type-79 cell per knot-line cell, 64 points each, certified bound") {
  const std::vector<double> knots = spline::boundary_restricted_knots({0, 0.5, 1});
  Eigen::MatrixXd points(125, 3);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) {
        auto g = [](int n) { return n == 0 ? 0.0 : n == 1 ? 1.0 / 6 : n == 2 ? 0.5 : n == 3 ? 5.0 / 6 : 1.0; };
        points.row(i + 5 * (j + 5 * k)) << g(i), g(j), g(k);
      }
  const spline::TSpline ts = spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points));
  io::BezierVtuOptions options;
  options.compress = false;
  const std::string text = io::serialize_bezier_vtu(ts, options);
  CHECK(text.find("NumberOfPoints=\"343\" NumberOfCells=\"8\"") != std::string::npos);  // (3·2 + 1)³ shared
  CHECK(text.find("Name=\"HigherOrderDegrees\" NumberOfComponents=\"3\"") != std::string::npos);
  CHECK(text.find("Name=\"scaled_jacobian_min\"") != std::string::npos);
  CHECK(text.find("RationalWeights") == std::string::npos);
  CHECK(text.find("<AppendedData encoding=\"raw\">") != std::string::npos);
}
