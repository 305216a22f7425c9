// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <string>

#include "core/volume/volume.h"

namespace volspline::io {

/// Decodes a single-file NIfTI-1 volume (.nii, or .nii.gz: the gzip is detected from its magic
/// bytes) held in memory: 3 dimensions (a 4th or 5th of size 1 is allowed), either byte order,
/// types uint8, int8, uint16, int16, uint32, int32, float32, float64, scl_slope / scl_inter
/// applied. Placement in NIfTI's RAS world: the sform when its code is set, else the qform
/// (quaternion, qfac, offsets), else the pixdim spacings at the origin.
/// Throws volspline::Error naming `name` on a bad magic (".hdr/.img pairs are not supported"),
/// bad dimensions, an unsupported datatype, truncated or oversized data, more than max_voxels
/// voxels (a .nii.gz stating a larger inflated size is refused before inflating), non-finite
/// samples.
volume::Volume parse_nifti(const std::string& bytes, const std::string& name,
                           std::int64_t max_voxels = std::int64_t{1} << 24);

}  // namespace volspline::io
