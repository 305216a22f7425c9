// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <string>

namespace volspline::io {

/// True: every build inflates gzip and zlib data (native builds with Debian's zlib; the WebAssembly
/// build with stb_image's inflate, as Debian's emscripten 3.1.6 cannot fetch its zlib port offline).
bool gzip_available();

/// The decompressed size a gzip stream's trailer states (ISIZE, the size modulo 2^32; a single
/// member). Throws volspline::Error naming `name` if the data is not gzip.
std::size_t gzip_stated_size(const char* data, std::size_t size, const std::string& name);

/// Inflates gzip (or zlib) data that must decompress to exactly `expected` bytes. Throws
/// volspline::Error naming `name` on corrupt, truncated or oversized data, and before allocating
/// anything when `expected` exceeds what deflate can produce from `size` bytes (its ratio is at
/// most 1032:1), so a hostile header cannot make it reserve memory the file cannot fill.
std::string gzip_inflate(const char* data, std::size_t size, std::size_t expected, const std::string& name);

}  // namespace volspline::io
