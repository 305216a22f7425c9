// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <string>

namespace volspline::io {

/// Deepest nesting JSON parsers may be handed: tinygltf's parse recurses once per level, so a
/// hostile file of a few kilobytes could otherwise exhaust the stack.
constexpr int kMaxJsonDepth = 512;

/// Largest nesting of arrays and objects in JSON text (strings and their escapes skipped), read
/// without recursion. Malformed text is measured as far as it goes; the parser reports the rest.
int json_nesting_depth(const char* text, std::size_t size);

/// Throws volspline::Error "<name>: JSON nests deeper than 512 levels" if the text does.
void check_json_depth(const char* text, std::size_t size, const std::string& name);

}  // namespace volspline::io
