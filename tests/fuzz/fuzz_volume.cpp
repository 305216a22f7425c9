// SPDX-License-Identifier: MIT
// libFuzzer target: parse_volume on arbitrary bytes must return a volume or throw
// volspline::Error; the first byte picks the format (NRRD, legacy VTK, MetaImage, VTI, NIfTI).
// Anything else (crash, sanitizer report, other exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/common/error.h"
#include "core/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  using volspline::io::VolumeFormat;
  const VolumeFormat formats[] = {VolumeFormat::Nrrd, VolumeFormat::Vtk, VolumeFormat::MetaImage, VolumeFormat::Vti,
                                  VolumeFormat::Nifti};
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    const auto v = volspline::io::parse_volume(bytes, formats[data[0] % 5], "fuzz");
    // Every reader promises the sample count of its dims and a unit direction per axis.
    if (v.samples.size() != v.num_voxels() || !(v.spacing.minCoeff() > 0) ||
        (v.direction.colwise().norm().array() - 1).abs().maxCoeff() > 1e-6)
      __builtin_trap();
  } catch (const volspline::Error&) {
  }
  return 0;
}
