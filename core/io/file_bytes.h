// SPDX-License-Identifier: MIT
#pragma once

#include <string>

namespace volspline::io {

/// Reads a whole file into memory.
/// Throws volspline::Error naming the path if it cannot be opened or read.
std::string read_file_bytes(const std::string& path);

/// Writes bytes to path atomically: a temporary file beside it, then rename, so a failure never
/// leaves a half-written output. Throws volspline::Error naming the path on failure.
void write_file_atomic(const std::string& path, const std::string& bytes);

/// Lower-case extension without the dot ("obj" for "a/b.OBJ"); empty if none.
std::string file_extension(const std::string& path);

}  // namespace volspline::io
