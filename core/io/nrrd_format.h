// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/io/volume_data.h"

namespace volspline::io {

/// Parses an NRRD header (`NRRD000x` magic; type, dimension 3, sizes, endian, encoding raw, ascii
/// or gzip, spacings or space directions, data file, byte skip, line skip) into a data layout;
/// attached data starts at its data_offset. Throws volspline::Error naming `name` and the field.
volume_data::DataLayout parse_nrrd_header(const std::string& bytes, const std::string& name);

}  // namespace volspline::io
