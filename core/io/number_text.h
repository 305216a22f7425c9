// SPDX-License-Identifier: MIT
#pragma once

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace volspline::io {

/// Appends the shortest %.Ng text (N = 15, 16 or 17) that reads back as exactly `value`.
/// printf-based rather than std::to_chars because Emscripten 3.1.6's libc++ lacks the double
/// overload, and native and WebAssembly builds must write the same bytes.
inline void append_number(std::string& out, double value) {
  char buffer[40];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof(buffer), "%.*g", precision, value);
    if (precision == 17 || std::strtod(buffer, nullptr) == value) break;
  }
  out.append(buffer);
}

/// Appends an integer in decimal.
inline void append_number(std::string& out, long long value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

}  // namespace volspline::io
