// SPDX-License-Identifier: MIT
#include "core/io/volume_vtu_writer.h"

#include <doctest/doctest.h>

using namespace volspline;

namespace {

volume::Volume two_by_two_by_three() {
  volume::Volume v;
  v.nx = 2;
  v.ny = 2;
  v.nz = 3;
  v.spacing = Eigen::Vector3d(1.0, 2.0, 0.5);
  for (int i = 0; i < 12; ++i) v.samples.push_back(static_cast<float>(i));
  return v;
}

}  // namespace

TEST_CASE("density vtu: voxel-centre points, 2 hexes in VTK order, error = reconstruction − sample") {
  const volume::Volume v = two_by_two_by_three();
  std::vector<double> recon(12);
  for (int i = 0; i < 12; ++i) recon[i] = i + 0.25;
  const std::string vtu = io::serialize_density_vtu(v, recon, Eigen::MatrixX3d());
  CHECK(vtu.find("NumberOfPoints=\"12\" NumberOfCells=\"2\"") != std::string::npos);
  CHECK(vtu.find("1 2 1\n") != std::string::npos);        // voxel (1, 1, 2) at (1, 2, 1)·spacing
  CHECK(vtu.find("0 1 3 2 4 5 7 6\n") != std::string::npos);  // bottom face counter-clockwise, then top
  const auto error = vtu.find("format=\"ascii\">\n", vtu.find("Name=\"error\"")) + 16;
  CHECK(vtu.substr(error, 5) == "0.25\n");
  CHECK(vtu.find("Name=\"uvw\"") == std::string::npos);
  Eigen::MatrixX3d uvw = Eigen::MatrixX3d::Zero(12, 3);
  CHECK(io::serialize_density_vtu(v, recon, uvw).find("Name=\"uvw\"") != std::string::npos);
}

TEST_CASE("frames vtu: one vertex per voxel with the three axes") {
  const volume::Volume v = two_by_two_by_three();
  volume::FrameField field{2, 2, 3, std::vector<Eigen::Matrix3d>(12, Eigen::Matrix3d::Identity())};
  const std::string vtu = io::serialize_frames_vtu(v, field);
  CHECK(vtu.find("NumberOfPoints=\"12\" NumberOfCells=\"12\"") != std::string::npos);
  for (const char* name : {"\"f0\"", "\"f1\"", "\"f2\""}) CHECK(vtu.find(name) != std::string::npos);
  const auto f2 = vtu.find("format=\"ascii\">\n", vtu.find("Name=\"f2\"")) + 16;
  CHECK(vtu.substr(f2, 6) == "0 0 1\n");
}
