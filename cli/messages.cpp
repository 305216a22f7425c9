// SPDX-License-Identifier: MIT
#include "cli/messages.h"

#include <cstdio>

namespace volspline::cli {

namespace {

struct FieldFlag {
  const char* field;
  const char* flag;
};

// Option fields of core/pipeline and core/io, and the flags of the commands that set them.
const FieldFlag kFieldFlags[] = {
    {"max_rms_rel", "--max-rms"},
    {"max_surface_error_rel", "--max-surface-error"},
    {"fit_damping", "--fit-damping"},
    {"hierarchy_depth", "--hierarchy-depth"},
    {"max_control_points", "--max-control-points"},
    {"max_levels", "--max-levels"},
    {"initial_cells", "--initial-cells"},
    {"area_balance_iterations", "--area-balance"},
    {"squeezed_below", "--squeezed-below"},
    {"min_scaled_jacobian", "--repair-jacobian"},
    {"threads", "--threads"},
    {"certificate_rounds", "--certificate-rounds"},
    {"corners", "--corners"},
    {"rois", "--roi"},
    {"magnification", "--magnification"},
    {"alpha", "--alpha"},
    {"grid", "--grid"},
    {"band", "--band"},
    {"height", "--height"},
    {"clusters", "--clusters"},
    {"min_gain_rate", "--min-gain-rate"},
    {"raw_layout", "--dims X,Y,Z and --type T"},
    {"max_pixels", "--max-pixels"},
    {"max_voxels", "--max-voxels"},
};

}  // namespace

std::string with_flag_names(const std::string& message) {
  std::string out;
  std::size_t at = 0;
  while (at < message.size()) {
    const std::size_t open = message.find('`', at);
    const std::size_t close = open == std::string::npos ? std::string::npos : message.find('`', open + 1);
    if (close == std::string::npos) {
      out.append(message, at, std::string::npos);
      break;
    }
    out.append(message, at, open - at);
    const std::string field = message.substr(open + 1, close - open - 1);
    bool identifier = !field.empty() && field[0] >= 'a' && field[0] <= 'z';
    for (char c : field) identifier = identifier && ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_');
    if (!identifier) {  // not a field (a file name with backticks, say): kept as it is
      out.append(message, open, close - open);
      at = close;
      continue;
    }
    const char* flag = nullptr;
    for (const FieldFlag& f : kFieldFlags)
      if (field == f.field) flag = f.flag;
    out += flag ? std::string(flag) : field;
    at = close + 1;
  }
  return out;
}

std::string printable(const std::string& message) {
  std::string out;
  out.reserve(message.size());
  auto escape = [&out](unsigned char c) {
    char hex[8];
    std::snprintf(hex, sizeof hex, "\\x%02x", c);
    out += hex;
  };
  for (std::size_t i = 0; i < message.size();) {
    const auto c = static_cast<unsigned char>(message[i]);
    if (c < 0x80) {
      if (c < 0x20 || c == 0x7F) escape(c);
      else out += static_cast<char>(c);
      ++i;
      continue;
    }
    // A well-formed UTF-8 sequence is kept unless it encodes a C1 control (U+0080..U+009F);
    // any other byte at or above 0x80 is escaped on its own.
    const int length = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    bool well_formed = length > 0 && i + length <= message.size();
    for (int k = 1; well_formed && k < length; ++k)
      well_formed = (static_cast<unsigned char>(message[i + k]) & 0xC0) == 0x80;
    const bool c1 = length == 2 && c == 0xC2 && static_cast<unsigned char>(message[i + 1]) <= 0x9F;
    if (well_formed && !c1) {
      out.append(message, i, static_cast<std::size_t>(length));
      i += static_cast<std::size_t>(length);
    } else {
      escape(c);
      ++i;
    }
  }
  return out;
}

}  // namespace volspline::cli
