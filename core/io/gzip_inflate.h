// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <string>

namespace volspline::io {

/// True when this build can inflate gzip data (native builds with Debian's zlib; the WebAssembly
/// build has no zlib, as emscripten's zlib port would have to be downloaded).
bool gzip_available();

/// Inflates gzip (or zlib) data that must decompress to exactly `expected` bytes. Throws
/// volspline::Error naming `name` on corrupt, truncated or oversized data, and before allocating
/// anything when `expected` exceeds what deflate can produce from `size` bytes (its ratio is at
/// most 1032:1), so a hostile header cannot make it reserve memory the file cannot fill.
std::string gzip_inflate(const char* data, std::size_t size, std::size_t expected, const std::string& name);

}  // namespace volspline::io
