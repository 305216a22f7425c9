// SPDX-License-Identifier: MIT
#include "core/io/vtk_volume_format.h"

#include <cstdint>
#include <vector>

#include "core/common/error.h"
#include "core/io/volume_header_text.h"

namespace volspline::io {

using namespace volume_text;
using volume_data::DataLayout;
using volume_data::Encoding;
using volume::SampleType;

namespace {

SampleType vtk_type(const std::string& text, const std::string& name) {
  return volume_data::sample_type_named(
      lower(text), {"unsigned_char", "char", "unsigned_short", "short", "unsigned_int", "int", "float", "double"}, text, name);
}

}  // namespace

DataLayout parse_vtk_volume_header(const std::string& bytes, const std::string& name) {
  std::size_t pos = 0;
  std::string line;
  if (!next_line(bytes, pos, line) || line.rfind("# vtk DataFile", 0) != 0)
    throw Error(name + ": not a legacy VTK file (missing '# vtk DataFile' line)");
  if (!next_line(bytes, pos, line)) throw Error(name + ": truncated VTK header (no title line)");
  if (!next_line(bytes, pos, line)) throw Error(name + ": truncated VTK header (no ASCII/BINARY line)");
  DataLayout layout;
  const std::string mode = lower(trim(line));
  if (mode == "ascii") {
    layout.encoding = Encoding::Ascii;
  } else if (mode == "binary") {
    layout.encoding = Encoding::Raw;
    layout.raw.big_endian = true;  // legacy VTK binary data is big-endian
  } else {
    throw Error(name + ": expected ASCII or BINARY, got '" + trim(line) + "'");
  }
  bool has_dataset = false, has_dims = false, has_scalars = false;
  long long point_count = -1;
  while (next_line(bytes, pos, line)) {
    const auto words = split_words(line);
    if (words.empty()) continue;
    const std::string keyword = lower(words[0]);
    const std::vector<std::string> args(words.begin() + 1, words.end());
    if (keyword == "dataset") {
      if (args.size() != 1 || lower(args[0]) != "structured_points")
        throw Error(name + ": only DATASET STRUCTURED_POINTS is supported, got '" + trim(line) + "'");
      has_dataset = true;
    } else if (!has_dataset) {
      throw Error(name + ": expected DATASET STRUCTURED_POINTS, got '" + trim(line) + "'");
    } else if (keyword == "dimensions") {
      layout.raw.dims = parse_dims(args, name, "DIMENSIONS");
      has_dims = true;
    } else if (keyword == "spacing" || keyword == "aspect_ratio") {
      layout.spacing = parse_spacing(args, name, "SPACING");
    } else if (keyword == "origin") {
      if (args.size() != 3) throw Error(name + ": ORIGIN needs 3 values, got " + std::to_string(args.size()));
      for (int k = 0; k < 3; ++k) layout.origin[k] = parse_real(args[k], name, "ORIGIN");
    } else if (keyword == "point_data") {
      if (args.size() != 1) throw Error(name + ": bad POINT_DATA line '" + trim(line) + "'");
      point_count = parse_integer(args[0], name, "POINT_DATA count");
    } else if (keyword == "scalars") {
      if (point_count < 0) throw Error(name + ": SCALARS before POINT_DATA");
      if (args.size() < 2 || args.size() > 3) throw Error(name + ": bad SCALARS line '" + trim(line) + "'");
      layout.raw.type = vtk_type(args[1], name);
      if (args.size() == 3 && parse_integer(args[2], name, "SCALARS component count") != 1)
        throw Error(name + ": only 1-component SCALARS are supported");
      has_scalars = true;
    } else if (keyword == "color_scalars") {
      // VTK writes every unsigned-char array as colour scalars: bytes in BINARY files, the bytes
      // divided by 255 in ASCII ones (vtkDataWriter), so ASCII values are scaled back and rounded.
      if (point_count < 0) throw Error(name + ": COLOR_SCALARS before POINT_DATA");
      if (args.size() != 2) throw Error(name + ": bad COLOR_SCALARS line '" + trim(line) + "'");
      if (parse_integer(args[1], name, "COLOR_SCALARS component count") != 1)
        throw Error(name + ": only 1-component COLOR_SCALARS are supported");
      layout.raw.type = SampleType::UInt8;
      if (layout.encoding == Encoding::Ascii) {
        layout.value_scale = 255;
        layout.round_values = true;
      }
      has_scalars = true;
      break;  // the data follows: COLOR_SCALARS have no LOOKUP_TABLE line
    } else if (keyword == "lookup_table") {
      if (!has_scalars) throw Error(name + ": LOOKUP_TABLE before SCALARS");
      break;
    } else if (keyword == "cell_data" || keyword == "field" || keyword == "vectors" || keyword == "tensors") {
      throw Error(name + ": unsupported VTK section '" + words[0] + "' (only point SCALARS are read)");
    } else {
      throw Error(name + ": unknown VTK keyword '" + words[0] + "'");
    }
  }
  if (!has_dims) throw Error(name + ": VTK header has no DIMENSIONS");
  if (!has_scalars) throw Error(name + ": VTK header has no SCALARS with LOOKUP_TABLE");
  const std::uint64_t count = volume_data::checked_voxel_count(layout.raw.dims, name);
  if (static_cast<std::uint64_t>(point_count) != count)
    throw Error(name + ": POINT_DATA " + std::to_string(point_count) + " does not match DIMENSIONS (" + std::to_string(count) + " points)");
  layout.data_offset = pos;
  return layout;
}

}  // namespace volspline::io
