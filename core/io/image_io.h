// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/common/image.h"

namespace volspline::io {

/// Decodes a PNG or JPEG held in memory into 8-bit grey, RGB or RGBA (grey+alpha becomes RGBA).
/// `name` is used in error messages. Throws volspline::Error naming `name` if the bytes are not
/// a decodable image.
Image decode_image(const std::string& bytes, const std::string& name);

/// Reads a PNG or JPEG file. Throws volspline::Error naming the path if it cannot be read or decoded.
Image read_image(const std::string& path);

/// Encodes an image as PNG bytes. Throws volspline::Error if the image is empty or malformed.
std::string encode_png(const Image& image);

/// Writes an image as PNG atomically. Throws volspline::Error naming the path on failure.
void write_png(const std::string& path, const Image& image);

}  // namespace volspline::io
