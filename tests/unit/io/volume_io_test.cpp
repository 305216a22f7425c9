// SPDX-License-Identifier: MIT
#include "core/io/volume_io.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <doctest/doctest.h>

#include "core/io/file_bytes.h"
#include "tests/unit/io/io_test_util.h"

using namespace volspline::io;
using volspline::io::test::error_of;
using volspline::io::test::has;
using volspline::volume::SampleType;
using volspline::volume::Volume;

namespace {

std::string temp_path(const std::string& file) {
  return (std::filesystem::temp_directory_path() / ("volspline_volume_io_" + file)).string();
}

// Samples 0, 1, ..., 11 of a 2x3x2 volume (sample value = flat index).
void check_ramp(const Volume& v) {
  REQUIRE(v.nx == 2);
  REQUIRE(v.ny == 3);
  REQUIRE(v.nz == 2);
  REQUIRE(v.samples.size() == 12);
  for (int i = 0; i < 12; ++i) CHECK(v.samples[i] == static_cast<float>(i));
  CHECK(v.index(1, 2, 1) == 11);
}

std::string ramp_bytes_u16(bool big_endian) {
  std::string bytes;
  for (int i = 0; i < 12; ++i) {
    const auto hi = static_cast<char>(i >> 8), lo = static_cast<char>(i & 255);
    bytes += big_endian ? std::string{hi, lo} : std::string{lo, hi};
  }
  return bytes;
}

std::string ramp_bytes_f32_big() {
  std::string bytes;
  for (int i = 0; i < 12; ++i) {
    const float f = static_cast<float>(i);
    unsigned char b[4];
    std::memcpy(b, &f, 4);
    // This test machine is little-endian (x86/arm64 Debian); write big-endian by reversing.
    for (int k = 3; k >= 0; --k) bytes += static_cast<char>(b[k]);
  }
  return bytes;
}

std::string ramp_bytes_u8() {
  std::string bytes;
  for (int i = 0; i < 12; ++i) bytes += static_cast<char>(i);
  return bytes;
}

}  // namespace

TEST_CASE("volume_io: formats from extensions and raw layouts from names") {
  CHECK(volume_format_from_path("a/b.RAW") == VolumeFormat::Raw);
  CHECK(volume_format_from_path("a.nrrd") == VolumeFormat::Nrrd);
  CHECK(volume_format_from_path("a.nhdr") == VolumeFormat::Nrrd);
  CHECK(volume_format_from_path("a.vtk") == VolumeFormat::Vtk);
  CHECK(volume_format_from_path("a.mhd") == VolumeFormat::MetaImage);
  CHECK(volume_format_from_path("a.mha") == VolumeFormat::MetaImage);
  CHECK(has(error_of([] { volume_format_from_path("x.png"); }), "x.png: unknown volume file extension 'png'"));
  const auto fuel = raw_layout_from_name("dir/fuel_64x64x64_uint8.raw");
  REQUIRE(fuel);
  CHECK(fuel->dims == std::array<int, 3>{64, 64, 64});
  CHECK(fuel->type == SampleType::UInt8);
  const auto tooth = raw_layout_from_name("my_tooth_103x94x161_float32.raw");
  REQUIRE(tooth);
  CHECK(tooth->dims == std::array<int, 3>{103, 94, 161});
  CHECK(tooth->type == SampleType::Float32);
  CHECK_FALSE(raw_layout_from_name("fuel.raw"));
  CHECK_FALSE(raw_layout_from_name("fuel_64x64_uint8.raw"));
  CHECK_FALSE(raw_layout_from_name("fuel_64x64x64_complex.raw"));
  CHECK_FALSE(raw_layout_from_name("fuel_64x0x64_uint8.raw"));
  CHECK(sample_type_from_name("uint16") == SampleType::UInt16);
  CHECK(has(error_of([] { sample_type_from_name("u8"); }), "unknown sample type 'u8'"));
}

TEST_CASE("volume_io: raw volumes of every byte order and their size errors") {
  RawVolumeLayout layout;
  layout.dims = {2, 3, 2};
  layout.type = SampleType::UInt8;
  check_ramp(parse_raw_volume(ramp_bytes_u8(), layout, "r.raw"));
  layout.type = SampleType::UInt16;
  Volume v = parse_raw_volume(ramp_bytes_u16(false), layout, "r.raw");
  check_ramp(v);
  CHECK(v.original_type == SampleType::UInt16);
  layout.big_endian = true;
  check_ramp(parse_raw_volume(ramp_bytes_u16(true), layout, "r.raw"));
  layout.type = SampleType::Float32;
  check_ramp(parse_raw_volume(ramp_bytes_f32_big(), layout, "r.raw"));

  layout.type = SampleType::UInt16;
  CHECK(has(error_of([&] { parse_raw_volume(ramp_bytes_u16(true).substr(0, 23), layout, "t.raw"); }),
            "t.raw: truncated data: expected 24 bytes, found 23"));
  CHECK(has(error_of([&] { parse_raw_volume(ramp_bytes_u16(true) + "x", layout, "t.raw"); }),
            "t.raw: size mismatch: expected 24 bytes, found 25"));
  layout.dims = {0, 3, 2};
  CHECK(has(error_of([&] { parse_raw_volume("", layout, "z.raw"); }), "z.raw: volume dimensions must be positive, got 0"));
  // A hostile header count must be refused before anything is allocated.
  layout.dims = {2000000000, 2000000000, 2000000000};
  CHECK(has(error_of([&] { parse_raw_volume("", layout, "h.raw"); }), "h.raw: volume of 2000000000x2000000000x2000000000 voxels is too large"));
  layout.dims = {1, 1, 1};
  layout.type = SampleType::Float32;
  layout.big_endian = false;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::string nan_bytes(4, '\0');
  std::memcpy(nan_bytes.data(), &nan, 4);
  CHECK(has(error_of([&] { parse_raw_volume(nan_bytes, layout, "n.raw"); }), "n.raw: sample 0 is not a finite number"));
}

TEST_CASE("volume_io: read_volume of raw files by name or by explicit layout") {
  const std::string path = temp_path("ramp_2x3x2_uint8.raw");
  write_file_atomic(path, ramp_bytes_u8());
  check_ramp(read_volume(path));
  const std::string plain = temp_path("ramp.raw");
  write_file_atomic(plain, ramp_bytes_u8());
  CHECK(has(error_of([&] { read_volume(plain); }), plain + ": raw volume needs its dims and type (`raw_layout`)"));
  VolumeReadOptions options;
  options.raw_layout = RawVolumeLayout{{2, 3, 2}, SampleType::UInt8, false};
  check_ramp(read_volume(plain, options));
  options.raw_layout->dims = {2, 3, 3};
  CHECK(has(error_of([&] { read_volume(plain, options); }), plain + ": truncated data: expected 18 bytes, found 12"));
  std::remove(path.c_str());
  std::remove(plain.c_str());
  CHECK(has(error_of([&] { read_volume(plain, options); }), "cannot open '" + plain + "'"));
}

TEST_CASE("volume_io: NRRD attached raw, ascii, big-endian and spacing") {
  const std::string header = "NRRD0004\n# comment\ntype: unsigned short\ndimension: 3\nsizes: 2 3 2\nendian: big\n"
                             "spacings: 0.5 1 2\nkey:=value\nencoding: raw\n\n";
  Volume v = parse_volume(header + ramp_bytes_u16(true), VolumeFormat::Nrrd, "a.nrrd");
  check_ramp(v);
  CHECK(v.spacing == Eigen::Vector3d(0.5, 1, 2));
  CHECK(v.original_type == SampleType::UInt16);
  const std::string ascii = "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 3 2\nencoding: ascii\n"
                            "space directions: (0,0,3) (0,4,0) (1,0,0)\n\n0 1 2 3\n4 5 6 7\n8 9 10 11\n";
  v = parse_volume(ascii, VolumeFormat::Nrrd, "b.nrrd");
  check_ramp(v);
  CHECK(v.spacing == Eigen::Vector3d(3, 4, 1));
  // byte skip -1: the data is the last bytes of the file.
  const std::string skip = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 3 2\nencoding: raw\nbyte skip: -1\n\nXYZ";
  check_ramp(parse_volume(skip + ramp_bytes_u8(), VolumeFormat::Nrrd, "c.nrrd"));
}

TEST_CASE("volume_io: NRRD errors name the file and the problem") {
  const std::string good = "type: uint8\ndimension: 3\nsizes: 2 3 2\nencoding: raw\n";
  auto err = [](const std::string& text) { return error_of([&] { parse_volume(text, VolumeFormat::Nrrd, "e.nrrd"); }); };
  CHECK(has(err("P5\n"), "e.nrrd: not an NRRD file"));
  CHECK(has(err("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 3 2\nencoding: gzip\n\n"), "e.nrrd: truncated gzip data"));
  CHECK(has(err("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 3 2\nencoding: bzip2\n\n"), "e.nrrd: unsupported encoding 'bzip2'"));
  CHECK(has(err("NRRD0004\ntype: complex\n"), "e.nrrd: unsupported sample type 'complex'"));
  CHECK(has(err("NRRD0004\ndimension: 2\n"), "e.nrrd: only 3-dimensional NRRD volumes are supported, got dimension 2"));
  CHECK(has(err("NRRD0004\nsizes: 2 3\n"), "e.nrrd: sizes needs 3 values, got 2"));
  CHECK(has(err("NRRD0004\nsizes: 2 -3 2\n"), "e.nrrd: sizes value -3 is not a positive size"));
  CHECK(has(err("NRRD0004\nsizes: 2 x 2\n"), "e.nrrd: bad sizes 'x'"));
  CHECK(has(err("NRRD0004\nspacings: 1 0 1\n"), "e.nrrd: spacings value 0 is not positive"));
  CHECK(has(err("NRRD0004\ngarbage\n"), "e.nrrd: bad NRRD header line 'garbage'"));
  CHECK(has(err("NRRD0004\ndimension: 3\nsizes: 2 3 2\nencoding: raw\n\n"), "e.nrrd: NRRD header has no type"));
  CHECK(has(err("NRRD0004\n" + good), "e.nrrd: NRRD header ends without a blank line before the data"));
  CHECK(has(err("NRRD0004\n" + good + "\n" + ramp_bytes_u8().substr(0, 5)), "e.nrrd: truncated data: expected 12 bytes, found 5"));
  CHECK(has(err("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 3 2\nencoding: ascii\n\n1 2 3 4 5 6 7 8 9 10 11 x"),
            "e.nrrd: truncated data: expected 12 values, found 11"));
  CHECK(has(err("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 200 200 200\nencoding: ascii\n\n1 2"),
            "e.nrrd: truncated data: expected 8000000 values"));
  CHECK(has(err("NRRD0004\n" + good + "data file: d.raw\n"), "e.nrrd: data is in the detached file 'd.raw'; read it with read_volume"));
  CHECK(has(err("NRRD0004\n" + good + "data file: LIST\n"), "e.nrrd: multi-file data ('LIST') is not supported"));
}

TEST_CASE("volume_io: NHDR with a detached data file, relative to the header") {
  const std::string data = temp_path("detached.raw");
  const std::string header = temp_path("detached.nhdr");
  write_file_atomic(data, "JUNK" + ramp_bytes_u16(false));
  write_file_atomic(header, "NRRD0005\ntype: uint16\ndimension: 3\nsizes: 2 3 2\nendian: little\nencoding: raw\nbyte skip: 4\n"
                            "data file: " + std::filesystem::path(data).filename().string() + "\n");
  check_ramp(read_volume(header));
  std::remove(data.c_str());
  CHECK(has(error_of([&] { read_volume(header); }), "cannot open '" + data + "'"));
  std::remove(header.c_str());
}

TEST_CASE("volume_io: legacy VTK structured points, ASCII and big-endian BINARY") {
  const std::string head = "# vtk DataFile Version 3.0\nramp\n";
  const std::string ascii = head + "ASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\nORIGIN 0 0 0\nSPACING 1 2 3\n"
                                   "POINT_DATA 12\nSCALARS density float 1\nLOOKUP_TABLE default\n0 1 2 3 4 5\n6 7 8 9 10 11\n";
  Volume v = parse_volume(ascii, VolumeFormat::Vtk, "a.vtk");
  check_ramp(v);
  CHECK(v.spacing == Eigen::Vector3d(1, 2, 3));
  const std::string binary = head + "BINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\nSPACING 1 1 1\n"
                                    "POINT_DATA 12\nSCALARS density unsigned_short\nLOOKUP_TABLE default\n";
  v = parse_volume(binary + ramp_bytes_u16(true) + "\n", VolumeFormat::Vtk, "b.vtk");
  check_ramp(v);
  CHECK(v.original_type == SampleType::UInt16);
  const std::string fbin = head + "BINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\n"
                                  "POINT_DATA 12\nSCALARS d float\nLOOKUP_TABLE default\n";
  check_ramp(parse_volume(fbin + ramp_bytes_f32_big(), VolumeFormat::Vtk, "f.vtk"));

  auto err = [](const std::string& text) { return error_of([&] { parse_volume(text, VolumeFormat::Vtk, "e.vtk"); }); };
  CHECK(has(err("hello\n"), "e.vtk: not a legacy VTK file"));
  CHECK(has(err(head + "TEXT\n"), "e.vtk: expected ASCII or BINARY, got 'TEXT'"));
  CHECK(has(err(head + "ASCII\nDATASET POLYDATA\n"), "e.vtk: only DATASET STRUCTURED_POINTS is supported"));
  CHECK(has(err(head + "ASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\nPOINT_DATA 13\nSCALARS d float\nLOOKUP_TABLE default\n"),
            "e.vtk: POINT_DATA 13 does not match DIMENSIONS (12 points)"));
  CHECK(has(err(head + "ASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\nPOINT_DATA 12\nSCALARS d float 3\n"),
            "e.vtk: only 1-component SCALARS are supported"));
  CHECK(has(err(head + "ASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\nPOINT_DATA 12\nSCALARS d bit\n"),
            "e.vtk: unsupported sample type 'bit'"));
  CHECK(has(err(head + "ASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\nPOINT_DATA 12\nVECTORS v float\n"),
            "e.vtk: unsupported VTK section 'VECTORS'"));
  CHECK(has(err(head + "ASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\n"), "e.vtk: VTK header has no SCALARS"));
  CHECK(has(err(binary + ramp_bytes_u16(true).substr(0, 20)), "e.vtk: truncated data: expected 24 bytes, found 20"));
  CHECK(has(err(head + "ASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\nPOINT_DATA 12\nSCALARS d float\nLOOKUP_TABLE default\n1 2 nan 4 5 6 7 8 9 10 11 12\n"),
            "e.vtk: sample 2 is not a finite number"));
}

TEST_CASE("volume_io: MetaImage .mha with LOCAL data and .mhd with a detached file") {
  const std::string mha = "ObjectType = Image\nNDims = 3\nDimSize = 2 3 2\nElementSpacing = 1 1 0.5\n"
                          "ElementByteOrderMSB = True\nElementType = MET_USHORT\nElementDataFile = LOCAL\n";
  Volume v = parse_volume(mha + ramp_bytes_u16(true), VolumeFormat::MetaImage, "a.mha");
  check_ramp(v);
  CHECK(v.spacing == Eigen::Vector3d(1, 1, 0.5));

  const std::string data = temp_path("meta.raw");
  const std::string header = temp_path("meta.mhd");
  write_file_atomic(data, ramp_bytes_u8());
  write_file_atomic(header, "NDims = 3\nDimSize = 2 3 2\nElementType = MET_UCHAR\nElementDataFile = " +
                                std::filesystem::path(data).filename().string() + "\n");
  check_ramp(read_volume(header));
  std::remove(data.c_str());
  std::remove(header.c_str());

  auto err = [](const std::string& text) { return error_of([&] { parse_volume(text, VolumeFormat::MetaImage, "e.mha"); }); };
  CHECK(has(err("NDims = 2\n"), "e.mha: only 3-dimensional MetaImage volumes are supported, got NDims 2"));
  CHECK(has(err("NDims = 3\nCompressedData = True\n"), "e.mha: MetaImage header has no DimSize"));
  CHECK(has(err("NDims = 3\nElementType = MET_LONG\n"), "e.mha: unsupported sample type 'MET_LONG'"));
  CHECK(has(err("NDims = 3\nDimSize = 2 3 2\nElementType = MET_UCHAR\n"), "e.mha: MetaImage header has no ElementDataFile"));
  CHECK(has(err("NDims = 3\nDimSize 2 3 2\n"), "e.mha: bad MetaImage header line 'DimSize 2 3 2'"));
  CHECK(has(err("NDims = 3\nDimSize = 2 3 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\nabc"),
            "e.mha: truncated data: expected 12 bytes, found 3"));
  CHECK(has(err("NDims = 3\nDimSize = 2 3 2\nElementType = MET_UCHAR\nElementDataFile = x.raw\n"),
            "e.mha: data is in the detached file 'x.raw'"));
}

TEST_CASE("volume_io: the shared test volumes have the dims and value ranges of SOURCES.md") {
  struct Expected {
    const char* file;
    int nx, ny, nz;
    double mean;
    std::size_t nonzero;
  };
  // Values from shared/data/volumes/SOURCES.md (mean given there to 2 decimals).
  const Expected expected[] = {{"fuel_64x64x64_uint8.raw", 64, 64, 64, 1.94, 13731},
                               {"neghip_64x64x64_uint8.raw", 64, 64, 64, 18.40, 121586},
                               {"tooth_103x94x161_uint8.raw", 103, 94, 161, 103.17, 1558787},
                               {"bucky_32x32x32_uint8.raw", 32, 32, 32, 35.85, 32637}};
  for (const auto& e : expected) {
    const Volume v = read_volume(std::string(VOLSPLINE_SHARED_DATA) + "/volumes/" + e.file);
    CHECK_MESSAGE(v.nx == e.nx, e.file);
    CHECK_MESSAGE(v.ny == e.ny, e.file);
    CHECK_MESSAGE(v.nz == e.nz, e.file);
    CHECK(v.original_type == SampleType::UInt8);
    CHECK(*std::min_element(v.samples.begin(), v.samples.end()) == 0.0f);
    CHECK(*std::max_element(v.samples.begin(), v.samples.end()) == 255.0f);
    double sum = 0.0;
    std::size_t nonzero = 0;
    for (float s : v.samples) {
      sum += s;
      nonzero += s != 0.0f;
    }
    CHECK_MESSAGE(std::abs(sum / v.samples.size() - e.mean) <= 0.005 + 1e-9, e.file);  // 2-decimal rounding
    CHECK_MESSAGE(nonzero == e.nonzero, e.file);
  }
}

TEST_CASE("volume_io: every truncation and byte change of valid files parses or throws volspline::Error") {
  const std::string nrrd = "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 2 3 2\nendian: big\nencoding: raw\n\n" + ramp_bytes_u16(true);
  const std::string vtk = "# vtk DataFile Version 3.0\nr\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\n"
                          "POINT_DATA 12\nSCALARS d unsigned_char\nLOOKUP_TABLE default\n" + ramp_bytes_u8();
  const std::string vtk_ascii = "# vtk DataFile Version 3.0\nr\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 2\n"
                                "POINT_DATA 12\nSCALARS d float\nLOOKUP_TABLE default\n0 1 2 3 4 5 6 7 8 9 10 11\n";
  const std::string mha = "NDims = 3\nDimSize = 2 3 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n" + ramp_bytes_u8();
  const std::pair<std::string, VolumeFormat> inputs[] = {
      {nrrd, VolumeFormat::Nrrd}, {vtk, VolumeFormat::Vtk}, {vtk_ascii, VolumeFormat::Vtk}, {mha, VolumeFormat::MetaImage}};
  int errors = 0;
  for (const auto& [text, format] : inputs) {
    CHECK(parse_volume(text, format, "ok").samples.size() == 12);
    auto attempt = [&, format = format](const std::string& bytes) {
      try {
        const Volume v = parse_volume(bytes, format, "m");
        CHECK(v.samples.size() == v.num_voxels());
      } catch (const volspline::Error&) {
        ++errors;
      }
    };
    for (std::size_t length = 0; length < text.size(); ++length) attempt(text.substr(0, length));
    for (std::size_t i = 0; i < text.size(); ++i)
      for (const char replacement : {'\0', '9', '\n', ' ', '-', static_cast<char>(0xff)}) {
        std::string changed = text;
        changed[i] = replacement;
        attempt(changed);
      }
  }
  CHECK(errors > 0);
}

TEST_CASE("volume_io: the remaining header errors of each format") {
  CHECK(has(error_of([] { parse_volume("x", VolumeFormat::Raw, "r.raw"); }), "r.raw: raw volumes need dims and type"));
  auto nrrd = [](const std::string& text) { return error_of([&] { parse_volume("NRRD0004\n" + text, VolumeFormat::Nrrd, "e.nrrd"); }); };
  CHECK(has(nrrd("endian: middle\n"), "e.nrrd: bad endian 'middle'"));
  CHECK(has(nrrd("byte skip: -2\n"), "e.nrrd: bad byte skip -2"));
  CHECK(has(nrrd("line skip: -1\n"), "e.nrrd: bad line skip -1"));
  CHECK(has(nrrd("space directions: (1,0,0) (0,1,0)\n"), "e.nrrd: space directions needs 3 vectors of 3 values"));
  CHECK(has(nrrd("space directions: (1,0,0) (0,0,0) (0,0,1)\n"), "e.nrrd: space direction 1 has zero length"));
  CHECK(has(nrrd("type: uint8\nsizes: 2 3 2\nencoding: raw\n\n"), "e.nrrd: NRRD header has no dimension"));
  CHECK(has(nrrd("type: uint8\ndimension: 3\nencoding: raw\n\n"), "e.nrrd: NRRD header has no sizes"));
  CHECK(has(nrrd("type: uint8\ndimension: 3\nsizes: 2 3 2\n\n"), "e.nrrd: NRRD header has no encoding"));
  CHECK(has(nrrd("type: uint8\ndimension: 3\nsizes: 2 3 2\nencoding: ascii\nbyte skip: -1\n\n"), "e.nrrd: byte skip -1 needs raw encoding"));
  CHECK(has(nrrd("type: uint8\ndimension: 3\nsizes: 2 3 2\nencoding: raw\nline skip: 5\n\nab\n"), "e.nrrd: truncated data: cannot skip 5 lines"));
  CHECK(has(nrrd("type: uint8\ndimension: 3\nsizes: 2 3 2\nencoding: raw\nbyte skip: 50\n\nab"), "e.nrrd: truncated data: byte skip 50 is past the end"));

  const std::string head = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n";
  auto vtk = [](const std::string& text) { return error_of([&] { parse_volume(text, VolumeFormat::Vtk, "e.vtk"); }); };
  CHECK(has(vtk("# vtk DataFile Version 3.0\n"), "e.vtk: truncated VTK header (no title line)"));
  CHECK(has(vtk("# vtk DataFile Version 3.0\nt\nASCII\nDIMENSIONS 2 3 2\n"), "e.vtk: expected DATASET STRUCTURED_POINTS, got 'DIMENSIONS 2 3 2'"));
  CHECK(has(vtk(head + "COLOR 1\n"), "e.vtk: unknown VTK keyword 'COLOR'"));
  CHECK(has(vtk(head + "DIMENSIONS 2 3 2\nSCALARS d float\n"), "e.vtk: SCALARS before POINT_DATA"));
  CHECK(has(vtk(head + "DIMENSIONS 2 3 2\nPOINT_DATA 12\nLOOKUP_TABLE default\n"), "e.vtk: LOOKUP_TABLE before SCALARS"));
  CHECK(has(vtk(head + "POINT_DATA 12\nSCALARS d float\nLOOKUP_TABLE default\n"), "e.vtk: VTK header has no DIMENSIONS"));
  CHECK(has(vtk(head + "SPACING 1 -1 1\n"), "e.vtk: SPACING value -1 is not positive"));

  auto mha = [](const std::string& text) { return error_of([&] { parse_volume(text, VolumeFormat::MetaImage, "e.mha"); }); };
  CHECK(has(mha("DimSize = 2 3 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n"), "e.mha: MetaImage header has no NDims"));
  CHECK(has(mha("NDims = 3\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n"), "e.mha: MetaImage header has no DimSize"));
  CHECK(has(mha("NDims = 3\nDimSize = 2 3 2\nElementDataFile = LOCAL\n"), "e.mha: MetaImage header has no ElementType"));
  CHECK(has(mha("NDims = 3\nBinaryData = False\n"), "e.mha: ASCII MetaImage data is not supported"));
  CHECK(has(mha("NDims = 3\nElementNumberOfChannels = 3\n"), "e.mha: only 1-channel MetaImage volumes are supported"));
  CHECK(has(mha("NDims = 3\nElementByteOrderMSB = maybe\n"), "e.mha: bad ElementByteOrderMSB 'maybe'"));
  CHECK(has(mha("NDims = 3\nElementDataFile = LIST\n"), "e.mha: multi-file data ('LIST') is not supported"));
}
