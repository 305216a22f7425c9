// SPDX-License-Identifier: MIT
#pragma once

#include <charconv>
#include <string>

namespace volspline::io {

/// Appends the shortest decimal text that reads back as exactly `value` (round-trip precision,
/// locale independent, deterministic).
inline void append_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

/// Appends an integer in decimal.
inline void append_number(std::string& out, long long value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

}  // namespace volspline::io
