// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/io/volume_data.h"

namespace volspline::io {

/// Parses a legacy VTK header (ASCII or big-endian BINARY, DATASET STRUCTURED_POINTS,
/// DIMENSIONS, SPACING, POINT_DATA, 1-component SCALARS with LOOKUP_TABLE) into a data layout;
/// the samples start at its data_offset. Throws volspline::Error naming `name` and the keyword.
volume_data::DataLayout parse_vtk_volume_header(const std::string& bytes, const std::string& name);

}  // namespace volspline::io
