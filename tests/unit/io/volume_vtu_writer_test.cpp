// SPDX-License-Identifier: MIT
#include "core/io/volume_vtu_writer.h"

#include <doctest/doctest.h>

#include "tests/unit/io/appended_array.h"
#include "core/io/vti_format.h"
#include "core/io/volume_vti_writer.h"

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

TEST_CASE("frames vtu: one vertex per voxel with the three axes") {
  const volume::Volume v = two_by_two_by_three();
  volume::FrameField field{2, 2, 3, std::vector<Eigen::Matrix3d>(12, Eigen::Matrix3d::Identity())};
  const std::string vtu = io::serialize_frames_vtu(v, field, false);
  CHECK(vtu.find("NumberOfPoints=\"12\" NumberOfCells=\"12\"") != std::string::npos);
  for (const char* name : {"\"f0\"", "\"f1\"", "\"f2\""}) CHECK(vtu.find(name) != std::string::npos);
  const std::vector<double> f2 = test::appended_array<double>(vtu, "f2");
  REQUIRE(f2.size() == 36);
  CHECK(f2[0] == 0.0);
  CHECK(f2[1] == 0.0);
  CHECK(f2[2] == 1.0);
  const std::vector<double> points = test::appended_array<double>(vtu, "Points");
  REQUIRE(points.size() == 36);
  CHECK(points[3 * 11 + 1] == 2.0);  // voxel (1, 1, 2) at (1, 2, 1)·spacing
  CHECK(points[3 * 11 + 2] == 1.0);
}

TEST_CASE("density vti: the voxels read back with their placement; error = reconstruction − sample") {
  volume::Volume v = two_by_two_by_three();
  v.origin = Eigen::Vector3d(1, -2, 3);
  v.direction << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  std::vector<double> recon(12);
  for (int i = 0; i < 12; ++i) recon[i] = i + 0.25;
  for (bool compress : {true, false}) {
    const std::string vti = io::serialize_density_vti(v, recon, Eigen::MatrixX3d(), compress);
    const volume::Volume back = io::parse_vti(vti, "density.vti");  // the active scalars: sample
    CHECK(back.nx == 2);
    CHECK(back.ny == 2);
    CHECK(back.nz == 3);
    CHECK(back.samples == v.samples);
    CHECK(back.spacing == v.spacing);
    CHECK(back.origin == v.origin);
    CHECK(back.direction == v.direction);
    CHECK(vti.find("Name=\"uvw\"") == std::string::npos);
    if (!compress) {
      const std::vector<double> error = test::appended_array<double>(vti, "error");
      REQUIRE(error.size() == 12);
      CHECK(error[5] == 0.25);
    }
  }
  Eigen::MatrixX3d uvw = Eigen::MatrixX3d::Zero(12, 3);
  CHECK(io::serialize_density_vti(v, recon, uvw).find("Name=\"uvw\"") != std::string::npos);
}
