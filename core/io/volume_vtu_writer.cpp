// SPDX-License-Identifier: MIT
#include "core/io/volume_vtu_writer.h"

#include <cassert>
#include <cstdint>

#include "core/io/file_bytes.h"
#include "core/io/vtk_xml_writer.h"

namespace volspline::io {

std::string serialize_frames_vtu(const volume::Volume& v, const volume::FrameField& field, bool compress) {
  const std::size_t n = v.num_voxels();
  assert(field.frames.size() == n);
  std::vector<double> points(3 * n);
  for (int z = 0; z < v.nz; ++z)
    for (int y = 0; y < v.ny; ++y)
      for (int x = 0; x < v.nx; ++x) {
        const Eigen::Vector3d p = v.voxel_position(x, y, z);
        for (int a = 0; a < 3; ++a) points[3 * v.index(x, y, z) + a] = p[a];
      }
  std::vector<std::int64_t> connectivity(n), offsets(n);
  for (std::size_t i = 0; i < n; ++i) connectivity[i] = std::int64_t(i), offsets[i] = std::int64_t(i + 1);
  std::vector<std::uint8_t> types(n, 1);  // VTK_VERTEX
  VtkXmlWriter writer(compress);
  std::string body = "<Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfCells=\"" + std::to_string(n) +
                     "\">\n<PointData Vectors=\"f0\">\n";
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> f(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      // Frame axes are rows in grid axes; the file's direction turns them into world vectors.
      const Eigen::Vector3d row = field.frames[i].row(axis).transpose();
      const Eigen::Vector3d world = v.world_is_grid() ? row : Eigen::Vector3d(v.direction * row);
      for (int a = 0; a < 3; ++a) f[3 * i + a] = world[a];
    }
    body += writer.add("f" + std::to_string(axis), f, 3);
  }
  body += "</PointData>\n<Points>\n" + writer.add("Points", points, 3) + "</Points>\n<Cells>\n";
  body += writer.add("connectivity", connectivity) + writer.add("offsets", offsets) + writer.add("types", types);
  body += "</Cells>\n</Piece>\n";
  return writer.document("UnstructuredGrid", "", body);
}

void write_frames_vtu(const std::string& path, const volume::Volume& volume, const volume::FrameField& field) {
  write_file_atomic(path, serialize_frames_vtu(volume, field));
}

}  // namespace volspline::io
