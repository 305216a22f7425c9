// SPDX-License-Identifier: MIT
#include "core/io/json_depth.h"

#include <algorithm>

#include "core/common/error.h"

namespace volspline::io {

int json_nesting_depth(const char* text, std::size_t size) {
  int depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < size; ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

void check_json_depth(const char* text, std::size_t size, const std::string& name) {
  if (json_nesting_depth(text, size) > kMaxJsonDepth)
    throw Error(name + ": JSON nests deeper than " + std::to_string(kMaxJsonDepth) + " levels");
}

}  // namespace volspline::io
