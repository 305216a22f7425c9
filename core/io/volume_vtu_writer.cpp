// SPDX-License-Identifier: MIT
#include "core/io/volume_vtu_writer.h"

#include <cassert>

#include "core/io/file_bytes.h"
#include "core/io/vtu_ascii.h"

namespace volspline::io {

namespace {

void append_voxel_points(std::string& out, const volume::Volume& v) {
  out += "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (int z = 0; z < v.nz; ++z)
    for (int y = 0; y < v.ny; ++y)
      for (int x = 0; x < v.nx; ++x) {
        const Eigen::Vector3d p = v.voxel_position(x, y, z);
        append_vtu_triple(out, p.x(), p.y(), p.z());
      }
  out += "</DataArray>\n</Points>\n";
}

}  // namespace

std::string serialize_density_vtu(const volume::Volume& v, const std::vector<double>& reconstruction,
                                  const Eigen::MatrixX3d& uvw) {
  assert(reconstruction.size() == v.num_voxels());
  const std::size_t cells = static_cast<std::size_t>(v.nx - 1) * (v.ny - 1) * (v.nz - 1);
  std::string out = vtu_header(v.num_voxels(), cells);
  append_voxel_points(out, v);
  out += "<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (int z = 0; z + 1 < v.nz; ++z)
    for (int y = 0; y + 1 < v.ny; ++y)
      for (int x = 0; x + 1 < v.nx; ++x) {
        const std::size_t c[8] = {v.index(x, y, z),         v.index(x + 1, y, z),     v.index(x + 1, y + 1, z),
                                  v.index(x, y + 1, z),     v.index(x, y, z + 1),     v.index(x + 1, y, z + 1),
                                  v.index(x + 1, y + 1, z + 1), v.index(x, y + 1, z + 1)};
        for (int k = 0; k < 8; ++k) out += std::to_string(c[k]) + (k == 7 ? "\n" : " ");
      }
  out += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t c = 1; c <= cells; ++c) out += std::to_string(8 * c) + "\n";
  out += "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t c = 0; c < cells; ++c) out += "12\n";
  out += "</DataArray>\n</Cells>\n<PointData Scalars=\"density\">\n";
  append_vtu_scalars(out, "density", reconstruction);
  std::vector<double> samples(v.samples.begin(), v.samples.end()), error(v.num_voxels());
  for (std::size_t i = 0; i < error.size(); ++i) error[i] = reconstruction[i] - samples[i];
  append_vtu_scalars(out, "sample", samples);
  append_vtu_scalars(out, "error", error);
  if (uvw.rows() == static_cast<Eigen::Index>(v.num_voxels())) {
    out += "<DataArray type=\"Float64\" Name=\"uvw\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < uvw.rows(); ++i) append_vtu_triple(out, uvw(i, 0), uvw(i, 1), uvw(i, 2));
    out += "</DataArray>\n";
  }
  out += "</PointData>\n";
  out += kVtuFooter;
  return out;
}

void write_density_vtu(const std::string& path, const volume::Volume& volume,
                       const std::vector<double>& reconstruction, const Eigen::MatrixX3d& uvw) {
  write_file_atomic(path, serialize_density_vtu(volume, reconstruction, uvw));
}

std::string serialize_frames_vtu(const volume::Volume& v, const volume::FrameField& field) {
  const std::size_t n = v.num_voxels();
  assert(field.frames.size() == n);
  std::string out = vtu_header(n, n);
  append_voxel_points(out, v);
  out += "<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i) out += std::to_string(i) + "\n";
  out += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 1; i <= n; ++i) out += std::to_string(i) + "\n";
  out += "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i) out += "1\n";
  out += "</DataArray>\n</Cells>\n<PointData Vectors=\"f0\">\n";
  for (int axis = 0; axis < 3; ++axis) {
    out += "<DataArray type=\"Float64\" Name=\"f" + std::to_string(axis) + "\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const auto& frame : field.frames) {
      // Frame axes are rows in grid axes; the file's direction turns them into world vectors.
      const Eigen::Vector3d row = frame.row(axis).transpose();
      const Eigen::Vector3d f = v.world_is_grid() ? row : Eigen::Vector3d(v.direction * row);
      append_vtu_triple(out, f.x(), f.y(), f.z());
    }
    out += "</DataArray>\n";
  }
  out += "</PointData>\n";
  out += kVtuFooter;
  return out;
}

void write_frames_vtu(const std::string& path, const volume::Volume& volume, const volume::FrameField& field) {
  write_file_atomic(path, serialize_frames_vtu(volume, field));
}

}  // namespace volspline::io
