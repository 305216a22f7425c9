// SPDX-License-Identifier: MIT
// Volumes written by VTK 9.1 (tests/data/volumes/make_vtk_volumes.py): every sample, the
// spacing and each voxel's world position as VTK placed it.
#include <string>

#include <doctest/doctest.h>

#include "core/io/file_bytes.h"
#include "core/io/volume_io.h"
#include "tests/unit/io/io_test_util.h"

using namespace volspline;

namespace {

const std::string kDir = VOLSPLINE_SOURCE_DIR "/tests/data/volumes/";

// 5x4x3 samples 0..59, spacing (0.5, 0.25, 2), voxel (0, 0, 0) at origin, axes along direction.
void check_volume(const volume::Volume& v, const Eigen::Vector3d& origin, const Eigen::Matrix3d& direction) {
  REQUIRE(v.nx == 5);
  REQUIRE(v.ny == 4);
  REQUIRE(v.nz == 3);
  REQUIRE(v.samples.size() == 60);
  for (int i = 0; i < 60; ++i) CHECK(v.samples[i] == static_cast<float>(i));
  CHECK((v.spacing - Eigen::Vector3d(0.5, 0.25, 2)).norm() < 1e-6);
  CHECK((v.origin - origin).norm() < 1e-5);
  CHECK((v.direction - direction).norm() < 1e-6);
  // Voxel (4, 3, 2): origin + direction · (2, 0.75, 4).
  CHECK((v.voxel_position(4, 3, 2) - (origin + direction * Eigen::Vector3d(2, 0.75, 4))).norm() < 1e-5);
}

const Eigen::Vector3d kOrigin(10, -20, 30);

}  // namespace

TEST_CASE("VTK-written legacy VTK uint8 volumes (COLOR_SCALARS, binary and ASCII) keep their origin") {
  for (const char* file : {"u8_bin.vtk", "u8_ascii.vtk"}) {
    CAPTURE(file);
    const volume::Volume v = io::read_volume(kDir + file);
    check_volume(v, kOrigin, Eigen::Matrix3d::Identity());
    CHECK(v.original_type == volume::SampleType::UInt8);
  }
}

TEST_CASE("VTK-written compressed MetaImage: .mha with LOCAL zlib data and .mhd with a .zraw file") {
  for (const char* file : {"u8.mha", "u8.mhd"}) {
    CAPTURE(file);
    check_volume(io::read_volume(kDir + file), kOrigin, Eigen::Matrix3d::Identity());
  }
  // parse_volume of the .mha bytes, as the browser reads it.
  check_volume(io::parse_volume(io::read_file_bytes(kDir + "u8.mha"), io::VolumeFormat::MetaImage, "u8.mha"), kOrigin,
               Eigen::Matrix3d::Identity());
}

TEST_CASE("VTK-written .vti in every data mode: ascii, binary, appended raw and base64, with and without zlib") {
  const Eigen::Matrix3d flip = Eigen::Vector3d(-1, -1, 1).asDiagonal();
  for (const char* file : {"d_ascii_n.vti", "d_ascii_z.vti", "d_binary_n.vti", "d_binary_z.vti", "d_appended_n.vti",
                           "d_appended_z.vti", "d_appended_b64.vti", "d_appended_enc.vti"}) {
    CAPTURE(file);
    check_volume(io::read_volume(kDir + file), kOrigin, flip);
  }
  // Float32, UInt64 headers, raw appended zlib, a rotated frame (VTK's Direction is row-major).
  Eigen::Matrix3d rotated;
  rotated << 0, 1, 0, -1, 0, 0, 0, 0, 1;
  const volume::Volume f = io::read_volume(kDir + "f32_u64_raw_z.vti");
  check_volume(f, kOrigin, rotated);
  CHECK(f.original_type == volume::SampleType::Float32);
}

TEST_CASE("VTK-written NIfTI-1: .nii with a qform, .nii.gz with an sform that mirrors x and y") {
  const volume::Volume n = io::read_volume(kDir + "n.nii");
  check_volume(n, kOrigin, Eigen::Matrix3d::Identity());
  CHECK(n.original_type == volume::SampleType::Int16);
  check_volume(io::read_volume(kDir + "n.nii.gz"), kOrigin, Eigen::Matrix3d::Identity());
  // VTK wrote srow = diag(-0.5, -0.25, 2) with translation (-5, 26, 37).
  const volume::Volume q = io::read_volume(kDir + "u16_q.nii.gz");
  check_volume(q, Eigen::Vector3d(-5, 26, 37), Eigen::Vector3d(-1, -1, 1).asDiagonal());
  CHECK(q.original_type == volume::SampleType::UInt16);
  CHECK(io::volume_format_from_path("a/b.NII.GZ") == io::VolumeFormat::Nifti);
  CHECK(io::volume_format_from_path("b.vti") == io::VolumeFormat::Vti);
}

TEST_CASE("NRRD space origin and space directions are kept (an LPS volume is not mirrored)") {
  const std::string header = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 1 1\nspace: left-posterior-superior\n"
                             "space directions: (-2,0,0) (0,-3,0) (0,0,4)\nspace origin: (5,6,7)\nencoding: raw\n\n";
  const volume::Volume v = io::parse_volume(header + std::string("\x01\x02", 2), io::VolumeFormat::Nrrd, "lps.nrrd");
  CHECK(v.spacing == Eigen::Vector3d(2, 3, 4));
  CHECK(v.origin == Eigen::Vector3d(5, 6, 7));
  CHECK(v.voxel_position(1, 0, 0) == Eigen::Vector3d(3, 6, 7));
}

TEST_CASE("truncations and byte changes of the VTK-written files parse or throw volspline::Error") {
  for (const char* file : {"d_binary_z.vti", "d_appended_b64.vti", "d_appended_enc.vti", "u8.mha", "n.nii.gz", "n.nii",
                           "u8_ascii.vtk"}) {
    CAPTURE(file);
    const std::string bytes = io::read_file_bytes(kDir + file);
    const io::VolumeFormat format = io::volume_format_from_path(file);
    for (std::size_t cut = 0; cut < bytes.size(); cut += 7) {
      try {
        io::parse_volume(bytes.substr(0, cut), format, file);
      } catch (const Error&) {
      }
      std::string changed = bytes;
      changed[cut] = static_cast<char>(changed[cut] ^ 0x5a);
      try {
        io::parse_volume(changed, format, file);
      } catch (const Error&) {
      }
    }
  }
  CHECK(io::test::has(io::test::error_of([] { io::parse_volume("<VTKFile type=\"ImageData\" compressor=\"vtkLZ4DataCompressor\">", io::VolumeFormat::Vti, "l.vti"); }),
                      "l.vti: compressor 'vtkLZ4DataCompressor' is not supported"));
}
