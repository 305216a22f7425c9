// SPDX-License-Identifier: MIT
// Error-message helpers of the io tests (the test meshes are in tests/unit/common/test_meshes.h).
#pragma once

#include <string>

#include "core/common/error.h"

namespace volspline::io::test {

/// The message of the volspline::Error that f throws, or "<no error>".
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const volspline::Error& e) {
    return e.what();
  }
  return "<no error>";
}

inline bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace volspline::io::test
