// SPDX-License-Identifier: MIT
#include "core/io/nifti_format.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/common/error.h"
#include "core/io/gzip_inflate.h"
#include "core/io/volume_data.h"

namespace volspline::io {

namespace {

using volume::SampleType;

constexpr std::size_t kHeaderSize = 348;

// Reads header fields at their NIfTI-1 byte offsets in the file's byte order.
class HeaderReader {
 public:
  HeaderReader(const std::string& bytes, bool swap) : bytes_(bytes), swap_(swap) {}
  template <typename T>
  T at(std::size_t offset) const {
    unsigned char buffer[sizeof(T)];
    std::memcpy(buffer, bytes_.data() + offset, sizeof(T));
    if (swap_)
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(buffer[i], buffer[sizeof(T) - 1 - i]);
    T value;
    std::memcpy(&value, buffer, sizeof(T));
    return value;
  }
  double real(std::size_t offset) const { return static_cast<double>(at<float>(offset)); }

 private:
  const std::string& bytes_;
  bool swap_;
};

SampleType nifti_type(int datatype, const std::string& name) {
  switch (datatype) {
    case 2: return SampleType::UInt8;
    case 4: return SampleType::Int16;
    case 8: return SampleType::Int32;
    case 16: return SampleType::Float32;
    case 64: return SampleType::Float64;
    case 256: return SampleType::Int8;
    case 512: return SampleType::UInt16;
    case 768: return SampleType::UInt32;
  }
  throw Error(name + ": unsupported NIfTI datatype " + std::to_string(datatype) +
              " (expected a scalar type: uint8, int8, uint16, int16, uint32, int32, float32 or float64)");
}

bool host_is_big_endian() {
  const std::uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 0;
}

}  // namespace

volume::Volume parse_nifti(const std::string& file_bytes, const std::string& name, std::int64_t max_voxels) {
  std::string inflated;
  const bool gzipped = file_bytes.size() >= 2 && static_cast<unsigned char>(file_bytes[0]) == 0x1f &&
                       static_cast<unsigned char>(file_bytes[1]) == 0x8b;
  if (gzipped) {
    // The header, an extension block and 8-byte samples at most: a larger stated size is a bomb.
    const std::size_t stated = gzip_stated_size(file_bytes.data(), file_bytes.size(), name);
    const double most = 65536.0 + 8.0 * static_cast<double>(std::max<std::int64_t>(max_voxels, 0));
    if (static_cast<double>(stated) > most)
      throw Error(name + ": inflates to " + std::to_string(stated) + " bytes, more than a volume within the limit " +
                  "`max_voxels` = " + std::to_string(max_voxels) + " can hold");
    inflated = gzip_inflate(file_bytes.data(), file_bytes.size(), stated, name);
  }
  const std::string& bytes = gzipped ? inflated : file_bytes;
  if (bytes.size() < kHeaderSize) throw Error(name + ": truncated NIfTI header (" + std::to_string(bytes.size()) + " bytes)");
  std::int32_t sizeof_hdr = 0;
  std::memcpy(&sizeof_hdr, bytes.data(), 4);
  bool swap = false;
  if (sizeof_hdr != static_cast<std::int32_t>(kHeaderSize)) {
    swap = true;
    if (HeaderReader(bytes, true).at<std::int32_t>(0) != static_cast<std::int32_t>(kHeaderSize))
      throw Error(name + ": not a NIfTI-1 file (sizeof_hdr is not 348)");
  }
  const std::string magic = bytes.substr(344, 4);
  if (magic == std::string("ni1\0", 4))
    throw Error(name + ": NIfTI .hdr/.img pairs are not supported (convert to a single .nii file)");
  if (magic != std::string("n+1\0", 4)) throw Error(name + ": not a NIfTI-1 file (missing n+1 magic)");
  const HeaderReader h(bytes, swap);
  const int ndim = h.at<std::int16_t>(40);
  if (ndim < 3 || ndim > 7) throw Error(name + ": only 3-dimensional NIfTI volumes are supported, got dim[0] = " + std::to_string(ndim));
  volume_data::DataLayout layout;
  for (int a = 0; a < 3; ++a) {
    const int size = h.at<std::int16_t>(42 + 2 * a);
    if (size < 1) throw Error(name + ": NIfTI dim[" + std::to_string(a + 1) + "] = " + std::to_string(size) + " is not a positive size");
    layout.raw.dims[a] = size;
  }
  for (int a = 3; a < ndim; ++a)
    if (h.at<std::int16_t>(42 + 2 * a) > 1)
      throw Error(name + ": only 3-dimensional NIfTI volumes are supported (dim[" + std::to_string(a + 1) + "] = " +
                  std::to_string(h.at<std::int16_t>(42 + 2 * a)) + ")");
  volume_data::check_voxel_limit(layout.raw.dims, max_voxels, name);
  layout.raw.type = nifti_type(h.at<std::int16_t>(70), name);
  layout.raw.big_endian = swap != host_is_big_endian();
  const double vox_offset = h.real(108);
  if (!(vox_offset >= static_cast<double>(kHeaderSize)) || vox_offset > static_cast<double>(bytes.size()) ||
      vox_offset != std::floor(vox_offset))
    throw Error(name + ": bad NIfTI vox_offset " + std::to_string(vox_offset));
  const double slope = h.real(112), inter = h.real(116);
  if (std::isfinite(slope) && slope != 0 && std::isfinite(inter)) {
    layout.value_scale = slope;
    layout.value_offset = inter;
  }
  Eigen::Vector3d pixdim;
  for (int a = 0; a < 3; ++a) {
    pixdim[a] = std::abs(h.real(80 + 4 * a));
    if (!(pixdim[a] > 0) || !std::isfinite(pixdim[a])) pixdim[a] = 1;
  }
  const int qform_code = h.at<std::int16_t>(252), sform_code = h.at<std::int16_t>(254);
  Eigen::Matrix3d steps = pixdim.asDiagonal();
  if (sform_code > 0) {
    // NIfTI-1 method 3: world = srow · (i, j, k, 1).
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) steps(r, c) = h.real(280 + 16 * r + 4 * c);
      layout.origin[r] = h.real(280 + 16 * r + 12);
    }
  } else if (qform_code > 0) {
    // NIfTI-1 method 2: world = R · diag(pixdim) · diag(1, 1, qfac) · (i, j, k) + qoffset.
    const double b = h.real(256), c = h.real(260), d = h.real(264);
    const double a = std::sqrt(std::max(0.0, 1.0 - (b * b + c * c + d * d)));
    Eigen::Matrix3d rotation;
    rotation << a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c),
                2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b),
                2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b;
    const double qfac = h.real(76) < 0 ? -1.0 : 1.0;
    steps = rotation * pixdim.asDiagonal();
    steps.col(2) *= qfac;
    for (int r = 0; r < 3; ++r) layout.origin[r] = h.real(268 + 4 * r);
  }
  volume_data::set_axes_from_steps(layout, steps, name, sform_code > 0 ? "sform" : "qform");
  return volume_data::decode_data(bytes, static_cast<std::size_t>(vox_offset), layout, name);
}

}  // namespace volspline::io
