// SPDX-License-Identifier: MIT
// libFuzzer target: the volume readers on arbitrary bytes must return a volume or throw
// volspline::Error; the first byte picks the format (NRRD, legacy VTK, MetaImage, VTI, NIfTI
// through parse_volume, or a raw volume with dims and type from the next 4 bytes). Anything else
// (crash, sanitizer report, other exception) is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/common/error.h"
#include "core/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace volspline;
  if (size == 0) return 0;
  using io::VolumeFormat;
  const VolumeFormat formats[] = {VolumeFormat::Nrrd, VolumeFormat::Vtk, VolumeFormat::MetaImage, VolumeFormat::Vti,
                                  VolumeFormat::Nifti};
  const int pick = data[0] % 6;
  try {
    volume::Volume v;
    if (pick == 5) {
      if (size < 5) return 0;
      io::RawVolumeLayout layout;
      for (int a = 0; a < 3; ++a) layout.dims[a] = 1 + data[1 + a] % 64;
      layout.type = static_cast<volume::SampleType>(data[4] % 8);
      layout.big_endian = data[4] & 8;
      v = io::parse_raw_volume(std::string(reinterpret_cast<const char*>(data) + 5, size - 5), layout, "fuzz.raw");
    } else {
      io::VolumeReadOptions options;
      options.max_voxels = std::int64_t{1} << 22;  // keeps each run within the fuzzer's memory limit
      v = io::parse_volume(std::string(reinterpret_cast<const char*>(data) + 1, size - 1), formats[pick], "fuzz",
                           options);
    }
    // Every reader promises the sample count of its dims, finite samples and a unit direction per axis.
    if (v.samples.size() != v.num_voxels() || !(v.spacing.minCoeff() > 0) ||
        (v.direction.colwise().norm().array() - 1).abs().maxCoeff() > 1e-6)
      __builtin_trap();
    for (float s : v.samples)
      if (!std::isfinite(s)) __builtin_trap();
  } catch (const Error&) {
  }
  return 0;
}
