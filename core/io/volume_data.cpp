// SPDX-License-Identifier: MIT
#include "core/io/volume_data.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <utility>

#include <Eigen/LU>

#include "core/common/error.h"
#include "core/io/gzip_inflate.h"
#include "core/io/volume_header_text.h"

namespace volspline::io::volume_data {

namespace {

using volume::SampleType;
using volume::Volume;

// Upper bound on the voxel count; the data size is checked against the file before allocating.
using volume_text::next_line;

constexpr std::uint64_t kMaxVoxels = std::uint64_t{1} << 31;

bool host_is_big_endian() {
  const std::uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 0;
}

template <typename T>
float load_sample(const char* p, bool swap) {
  unsigned char buffer[sizeof(T)];
  std::memcpy(buffer, p, sizeof(T));
  if (swap)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(buffer[i], buffer[sizeof(T) - 1 - i]);
  T value;
  std::memcpy(&value, buffer, sizeof(T));
  return static_cast<float>(value);
}

float load(const char* p, SampleType type, bool swap) {
  switch (type) {
    case SampleType::UInt8: return load_sample<std::uint8_t>(p, false);
    case SampleType::Int8: return load_sample<std::int8_t>(p, false);
    case SampleType::UInt16: return load_sample<std::uint16_t>(p, swap);
    case SampleType::Int16: return load_sample<std::int16_t>(p, swap);
    case SampleType::UInt32: return load_sample<std::uint32_t>(p, swap);
    case SampleType::Int32: return load_sample<std::int32_t>(p, swap);
    case SampleType::Float32: return load_sample<float>(p, swap);
    case SampleType::Float64: return load_sample<double>(p, swap);
  }
  return 0.0f;
}

Volume make_volume(const RawVolumeLayout& layout, const Eigen::Vector3d& spacing) {
  Volume volume;
  volume.nx = layout.dims[0];
  volume.ny = layout.dims[1];
  volume.nz = layout.dims[2];
  volume.spacing = spacing;
  volume.original_type = layout.type;
  return volume;
}

void check_finite(const Volume& volume, const std::string& name) {
  for (std::size_t i = 0; i < volume.samples.size(); ++i)
    if (!std::isfinite(volume.samples[i]))
      throw Error(name + ": sample " + std::to_string(i) + " is not a finite number");
}

Volume decode_ascii(const std::string& bytes, std::size_t begin, const RawVolumeLayout& layout,
                    const Eigen::Vector3d& spacing, const std::string& name) {
  const std::uint64_t count = checked_voxel_count(layout.dims, name);
  // Each value takes at least one character: reject impossible counts before allocating.
  if (begin > bytes.size() || bytes.size() - begin < count)
    throw Error(name + ": truncated data: expected " + std::to_string(count) + " values");
  Volume volume = make_volume(layout, spacing);
  volume.samples.resize(count);
  const char* p = bytes.c_str() + begin;
  for (std::uint64_t i = 0; i < count; ++i) {
    char* end = nullptr;
    const double value = std::strtod(p, &end);
    if (end == p)
      throw Error(name + ": truncated data: expected " + std::to_string(count) + " values, found " + std::to_string(i));
    if (!std::isfinite(value)) throw Error(name + ": sample " + std::to_string(i) + " is not a finite number");
    volume.samples[i] = static_cast<float>(value);
    p = end;
  }
  check_finite(volume, name);
  return volume;
}
}  // namespace

void check_voxel_limit(const std::array<int, 3>& dims, std::int64_t max_voxels, const std::string& name) {
  const std::uint64_t count = checked_voxel_count(dims, name);
  if (count > static_cast<std::uint64_t>(std::max<std::int64_t>(max_voxels, 0)))
    throw Error(name + ": volume of " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" +
                std::to_string(dims[2]) + " voxels is above the limit `max_voxels` = " + std::to_string(max_voxels));
}

std::uint64_t checked_voxel_count(const std::array<int, 3>& dims, const std::string& name) {
  std::uint64_t count = 1;
  for (int d : dims) {
    if (d < 1) throw Error(name + ": volume dimensions must be positive, got " + std::to_string(d));
    count *= static_cast<std::uint64_t>(d);
    if (count > kMaxVoxels) throw Error(name + ": volume of " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]) + " voxels is too large");
  }
  return count;
}

Volume decode_binary(const char* data, std::size_t size, const RawVolumeLayout& layout, const Eigen::Vector3d& spacing,
                     bool exact, const std::string& name) {
  const std::uint64_t count = checked_voxel_count(layout.dims, name);
  const std::uint64_t needed = count * static_cast<std::uint64_t>(volume::sample_type_size(layout.type));
  if (size < needed)
    throw Error(name + ": truncated data: expected " + std::to_string(needed) + " bytes, found " + std::to_string(size));
  if (exact && size != needed)
    throw Error(name + ": size mismatch: expected " + std::to_string(needed) + " bytes, found " + std::to_string(size));
  Volume volume = make_volume(layout, spacing);
  volume.samples.resize(count);
  const bool swap = layout.big_endian != host_is_big_endian();
  const int step = volume::sample_type_size(layout.type);
  for (std::uint64_t i = 0; i < count; ++i) volume.samples[i] = load(data + i * step, layout.type, swap);
  check_finite(volume, name);
  return volume;
}

namespace {

// The samples as stored, after the layout's skips and encoding.
Volume decode_samples(const std::string& bytes, std::size_t begin, const DataLayout& layout, const std::string& name) {
  std::size_t pos = begin;
  std::string line;
  for (long long i = 0; i < layout.line_skip; ++i)
    if (!next_line(bytes, pos, line)) throw Error(name + ": truncated data: cannot skip " + std::to_string(layout.line_skip) + " lines");
  if (layout.encoding == Encoding::Ascii) return decode_ascii(bytes, pos, layout.raw, layout.spacing, name);
  if (layout.encoding == Encoding::Gzip) {
    // NRRD: the byte skip of compressed data counts decompressed bytes (before the samples).
    const std::uint64_t count = checked_voxel_count(layout.raw.dims, name);
    const std::uint64_t needed = count * static_cast<std::uint64_t>(volume::sample_type_size(layout.raw.type)) +
                                 static_cast<std::uint64_t>(layout.byte_skip);
    const std::string plain = gzip_inflate(bytes.data() + pos, bytes.size() - pos, static_cast<std::size_t>(needed), name);
    const std::size_t skip = static_cast<std::size_t>(layout.byte_skip);
    return decode_binary(plain.data() + skip, plain.size() - skip, layout.raw, layout.spacing, false, name);
  }
  if (layout.byte_skip == -1) {
    const std::uint64_t count = checked_voxel_count(layout.raw.dims, name);
    const std::uint64_t needed = count * static_cast<std::uint64_t>(volume::sample_type_size(layout.raw.type));
    if (bytes.size() - pos < needed)
      throw Error(name + ": truncated data: expected " + std::to_string(needed) + " bytes, found " + std::to_string(bytes.size() - pos));
    pos = bytes.size() - static_cast<std::size_t>(needed);
  } else {
    if (static_cast<std::uint64_t>(layout.byte_skip) > bytes.size() - pos)
      throw Error(name + ": truncated data: byte skip " + std::to_string(layout.byte_skip) + " is past the end");
    pos += static_cast<std::size_t>(layout.byte_skip);
  }
  return decode_binary(bytes.data() + pos, bytes.size() - pos, layout.raw, layout.spacing, false, name);
}

}  // namespace

volume::SampleType sample_type_named(const std::string& key, const std::array<const char*, 8>& names,
                                     const std::string& shown, const std::string& name) {
  constexpr SampleType kOrder[8] = {SampleType::UInt8,  SampleType::Int8,  SampleType::UInt16,  SampleType::Int16,
                                    SampleType::UInt32, SampleType::Int32, SampleType::Float32, SampleType::Float64};
  for (int i = 0; i < 8; ++i)
    if (key == names[i]) return kOrder[i];
  throw Error(name + ": unsupported sample type '" + shown + "'");
}

void set_axes_from_steps(DataLayout& layout, const Eigen::Matrix3d& steps, const std::string& name, const std::string& what) {
  for (int a = 0; a < 3; ++a) {
    const double length = steps.col(a).norm();
    if (!(length > 0) || !std::isfinite(length))
      throw Error(name + ": " + what + " axis " + std::to_string(a) + " has zero length");
    layout.spacing[a] = length;
    layout.direction.col(a) = steps.col(a) / length;
  }
  if (!(std::abs(layout.direction.determinant()) > 1e-6))
    throw Error(name + ": " + what + " axes are linearly dependent");
}

Volume decode_data(const std::string& bytes, std::size_t begin, const DataLayout& layout, const std::string& name) {
  Volume volume = decode_samples(bytes, begin, layout, name);
  volume.origin = layout.origin;
  volume.direction = layout.direction;
  if (layout.value_scale != 1 || layout.value_offset != 0 || layout.round_values) {
    for (float& x : volume.samples) {
      const double value = layout.value_scale * x + layout.value_offset;
      x = static_cast<float>(layout.round_values ? std::round(value) : value);
    }
    check_finite(volume, name);
  }
  return volume;
}

}  // namespace volspline::io::volume_data
