// SPDX-License-Identifier: MIT
#include "core/io/volume_vti_writer.h"

#include <cassert>
#include <cstdio>

#include "core/io/file_bytes.h"
#include "core/io/vtk_xml_writer.h"

namespace volspline::io {

namespace {

std::string numbers(const double* x, int count) {
  std::string out;
  char buffer[32];
  for (int i = 0; i < count; ++i) {
    std::snprintf(buffer, sizeof buffer, "%.17g", x[i]);
    out += (i ? " " : "") + std::string(buffer);
  }
  return out;
}

}  // namespace

std::string serialize_density_vti(const volume::Volume& v, const std::vector<double>& reconstruction,
                                  const Eigen::MatrixX3d& uvw, bool compress) {
  assert(reconstruction.size() == v.num_voxels());
  VtkXmlWriter writer(compress);
  const std::string extent =
      "0 " + std::to_string(v.nx - 1) + " 0 " + std::to_string(v.ny - 1) + " 0 " + std::to_string(v.nz - 1);
  std::vector<double> samples(v.samples.begin(), v.samples.end()), error(v.num_voxels());
  for (std::size_t i = 0; i < error.size(); ++i) error[i] = reconstruction[i] - samples[i];
  std::string body = "<Piece Extent=\"" + extent + "\">\n<PointData Scalars=\"sample\">\n";
  body += writer.add("sample", samples);
  body += writer.add("density", reconstruction);
  body += writer.add("error", error);
  if (uvw.rows() == static_cast<Eigen::Index>(v.num_voxels())) {
    std::vector<double> flat(std::size_t(uvw.rows()) * 3);
    for (Eigen::Index i = 0; i < uvw.rows(); ++i)
      for (int a = 0; a < 3; ++a) flat[std::size_t(i) * 3 + a] = uvw(i, a);
    body += writer.add("uvw", flat, 3);
  }
  body += "</PointData>\n<CellData>\n</CellData>\n</Piece>\n";
  // VTK's Direction is row-major; its columns are the index axes' world directions.
  double direction[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) direction[3 * r + c] = v.direction(r, c);
  const std::string attributes = "WholeExtent=\"" + extent + "\" Origin=\"" + numbers(v.origin.data(), 3) +
                                 "\" Spacing=\"" + numbers(v.spacing.data(), 3) + "\" Direction=\"" +
                                 numbers(direction, 9) + "\"";
  return writer.document("ImageData", attributes, body);
}

void write_density_vti(const std::string& path, const volume::Volume& volume,
                       const std::vector<double>& reconstruction, const Eigen::MatrixX3d& uvw) {
  write_file_atomic(path, serialize_density_vti(volume, reconstruction, uvw));
}

}  // namespace volspline::io
