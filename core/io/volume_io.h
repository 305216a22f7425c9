// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "core/io/raw_volume_format.h"
#include "core/volume/volume.h"

namespace volspline::io {

/// Volume file formats that volspline reads.
enum class VolumeFormat { Raw, Nrrd, Vtk, MetaImage, Vti, Nifti };

/// Options of read_volume and parse_volume.
struct VolumeReadOptions {
  std::optional<RawVolumeLayout> raw_layout;  ///< if unset, raw files need a name like fuel_64x64x64_uint8.raw
  /// Largest nx·ny·nz accepted, checked on the header before any sample is allocated or
  /// inflated (16 Mi voxels: 256³; the jobs hold tens of bytes per voxel).
  std::int64_t max_voxels = std::int64_t{1} << 24;
};

/// Format from a file name's extension: raw, nrrd/nhdr, vtk, mhd/mha, vti, nii/nii.gz.
/// Throws volspline::Error naming the path if the extension is unknown.
VolumeFormat volume_format_from_path(const std::string& path);

/// Decodes an NRRD (attached data), legacy VTK STRUCTURED_POINTS (ASCII or BINARY, SCALARS or
/// COLOR_SCALARS), MetaImage .mha (ElementDataFile = LOCAL, raw or zlib), VTK XML ImageData .vti
/// or NIfTI-1 .nii/.nii.gz held in memory, with the file's origin and axis directions (NRRD
/// space origin / space directions, VTK ORIGIN, MetaImage Offset / TransformMatrix, VTI Origin /
/// Direction, NIfTI sform / qform) in Volume::origin and Volume::direction. `name` is used in
/// error messages.
/// Throws volspline::Error naming `name` and the problem on: bad magic, missing or bad header
/// fields, dimension other than 3, unsupported type or encoding,
/// detached data (use read_volume), truncated or oversized data, more voxels than
/// options.max_voxels, non-finite samples.
volume::Volume parse_volume(const std::string& bytes, VolumeFormat format, const std::string& name,
                            const VolumeReadOptions& options = {});

/// Reads a volume file; the format comes from the extension. NHDR and MetaImage .mhd headers may
/// name a detached data file, resolved relative to the header's folder. Raw files take their
/// layout from options.raw_layout or else from the file name.
/// Throws volspline::Error naming the file and the problem (see parse_volume, parse_raw_volume).
volume::Volume read_volume(const std::string& path, const VolumeReadOptions& options = {});

}  // namespace volspline::io
