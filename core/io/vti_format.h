// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <string>

#include "core/volume/volume.h"

namespace volspline::io {

/// Decodes a VTK XML ImageData file (.vti, as VTK and ParaView write it) held in memory: one
/// piece, its PointData's active Scalars (else its first 1-component array), the array in
/// ascii, binary (base64) or appended (raw or base64) format, uncompressed or with
/// vtkZLibDataCompressor blocks, UInt32 or UInt64 headers, either byte order; WholeExtent,
/// Origin, Spacing and Direction place the voxels in the world.
/// Throws volspline::Error naming `name` on a malformed file, an unsupported compressor (LZ4,
/// LZMA), type or component count, truncated or corrupt data, more than max_voxels voxels
/// (checked before any data is decoded), non-finite samples.
volume::Volume parse_vti(const std::string& bytes, const std::string& name,
                         std::int64_t max_voxels = std::int64_t{1} << 24);

}  // namespace volspline::io
