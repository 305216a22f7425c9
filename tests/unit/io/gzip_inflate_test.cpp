// SPDX-License-Identifier: MIT
#include "core/io/gzip_inflate.h"

#include <string>

#include <doctest/doctest.h>
#include <zlib.h>

#include "core/io/volume_io.h"
#include "tests/unit/io/io_test_util.h"

using namespace volspline;
using io::test::has;

namespace {

// gzip (RFC 1952) of `plain`, made with zlib's deflate.
std::string gzip_of(const std::string& plain) {
  z_stream s{};
  REQUIRE(deflateInit2(&s, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) == Z_OK);
  std::string out(deflateBound(&s, plain.size()) + 32, '\0');
  s.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(plain.data()));
  s.avail_in = static_cast<uInt>(plain.size());
  s.next_out = reinterpret_cast<Bytef*>(out.data());
  s.avail_out = static_cast<uInt>(out.size());
  REQUIRE(deflate(&s, Z_FINISH) == Z_STREAM_END);
  out.resize(out.size() - s.avail_out);
  deflateEnd(&s);
  return out;
}

std::string gzip_ramp_plain(int n) {
  std::string bytes;
  for (int i = 0; i < n; ++i) bytes += static_cast<char>(i);
  return bytes;
}

const std::string kGzipHeader = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 3 2\nencoding: gzip\nspacings: 1 2 3\n";

std::string gzip_error(const std::string& bytes) {
  return io::test::error_of([&] { io::parse_volume(bytes, io::VolumeFormat::Nrrd, "g.nrrd"); });
}

}  // namespace

TEST_CASE("gzip NRRD: samples, spacing and a byte skip in the decompressed data") {
  REQUIRE(io::gzip_available());
  const volume::Volume v = io::parse_volume(kGzipHeader + "\n" + gzip_of(gzip_ramp_plain(12)), io::VolumeFormat::Nrrd, "g.nrrd");
  REQUIRE(v.samples.size() == 12);
  for (int i = 0; i < 12; ++i) CHECK(v.samples[i] == static_cast<float>(i));
  CHECK(v.spacing == Eigen::Vector3d(1, 2, 3));
  const volume::Volume skipped = io::parse_volume(kGzipHeader + "byte skip: 3\n\n" + gzip_of("XYZ" + gzip_ramp_plain(12)),
                                                  io::VolumeFormat::Nrrd, "g.nrrd");
  for (int i = 0; i < 12; ++i) CHECK(skipped.samples[i] == static_cast<float>(i));
}

TEST_CASE("gzip NRRD: truncated, corrupt, short, long and hostile data are clear errors") {
  const std::string gz = gzip_of(gzip_ramp_plain(12));
  CHECK(has(gzip_error(kGzipHeader + "\n" + gz.substr(0, gz.size() - 6)), "g.nrrd: truncated gzip data"));
  std::string corrupt = gz;
  corrupt[12] = static_cast<char>(corrupt[12] ^ 0x5a);
  corrupt[13] = static_cast<char>(corrupt[13] ^ 0xa5);
  const std::string e = gzip_error(kGzipHeader + "\n" + corrupt);
  CHECK((has(e, "g.nrrd: corrupt gzip data") || has(e, "g.nrrd: truncated")));
  CHECK(has(gzip_error(kGzipHeader + "\n" + gzip_of(gzip_ramp_plain(6))), "g.nrrd: truncated data: gzip data decompresses to 6 bytes, expected 12"));
  CHECK(has(gzip_error(kGzipHeader + "\n" + gzip_of(gzip_ramp_plain(20))), "g.nrrd: gzip data decompresses to more than the 12 bytes"));
  CHECK(has(gzip_error(kGzipHeader + "\n" + "not gzip at all"), "g.nrrd: corrupt gzip data"));
  // 10⁹ samples claimed by 32 bytes: refused before any allocation.
  const std::string hostile = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1000 1000 1000\nencoding: gzip\n\n" + gz;
  CHECK(has(gzip_error(hostile), "g.nrrd: volume of 1000x1000x1000 voxels is above the limit `max_voxels`"));
}
