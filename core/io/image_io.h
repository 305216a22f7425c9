// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <string>

#include "core/common/image.h"

namespace volspline::io {

/// Largest image decode_image accepts, checked on the header before any pixel is allocated.
struct ImageLimits {
  std::int64_t max_pixels = std::int64_t{1} << 26;  ///< width × height (64 Mi pixels, 256 MiB as RGBA)
};

/// Decodes a PNG or JPEG held in memory into 8-bit grey, RGB or RGBA (grey+alpha becomes RGBA).
/// `name` is used in error messages. Throws volspline::Error naming `name` and the problem if the
/// bytes are not a PNG or JPEG, are truncated or corrupt (JPEG Huffman tables are checked before
/// decoding), or the image has more than limits.max_pixels pixels.
Image decode_image(const std::string& bytes, const std::string& name, const ImageLimits& limits = {});

/// Reads a PNG or JPEG file. Throws volspline::Error naming the path if it cannot be read or decoded.
Image read_image(const std::string& path, const ImageLimits& limits = {});

/// Encodes an image as PNG bytes. Throws volspline::Error if the image is empty or malformed.
std::string encode_png(const Image& image);

/// Writes an image as PNG atomically. Throws volspline::Error naming the path on failure.
void write_png(const std::string& path, const Image& image);

}  // namespace volspline::io
