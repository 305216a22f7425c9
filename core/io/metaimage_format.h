// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/io/volume_data.h"

namespace volspline::io {

/// Parses a MetaImage header (.mha/.mhd: NDims 3, DimSize, ElementType, ElementSpacing,
/// byte order, HeaderSize, ElementDataFile LOCAL or a file name) into a data layout.
/// Throws volspline::Error naming `name` and the key.
volume_data::DataLayout parse_metaimage_header(const std::string& bytes, const std::string& name);

}  // namespace volspline::io
