// SPDX-License-Identifier: MIT
#include "core/io/image_io.h"

#include <climits>
#include <cstring>

#include "core/common/error.h"
#include "core/io/file_bytes.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#include <stb_image.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STBI_WRITE_NO_STDIO
#include <stb_image_write.h>

namespace volspline::io {

namespace {

void append_bytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}

}  // namespace

Image decode_image(const std::string& bytes, const std::string& name) {
  if (bytes.empty()) throw Error("'" + name + "': empty file, expected a PNG or JPEG image");
  if (bytes.size() > static_cast<std::size_t>(INT_MAX)) throw Error("'" + name + "': file too large");
  int width = 0, height = 0, channels_in_file = 0;
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  if (!stbi_info_from_memory(data, static_cast<int>(bytes.size()), &width, &height, &channels_in_file))
    throw Error("'" + name + "': not a readable PNG or JPEG image (" + stbi_failure_reason() + ")");
  // Grey+alpha has no 8-bit interchange layout of its own here, so it is widened to RGBA.
  const int channels = channels_in_file == 2 ? 4 : channels_in_file;
  stbi_uc* pixels = stbi_load_from_memory(data, static_cast<int>(bytes.size()), &width, &height,
                                          &channels_in_file, channels);
  if (!pixels) throw Error("'" + name + "': cannot decode image (" + stbi_failure_reason() + ")");
  Image image;
  image.width = width;
  image.height = height;
  image.channels = channels;
  image.pixels.assign(pixels, pixels + static_cast<std::size_t>(width) * height * channels);
  stbi_image_free(pixels);
  return image;
}

Image read_image(const std::string& path) { return decode_image(read_file_bytes(path), path); }

std::string encode_png(const Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.channels < 1 || image.channels > 4 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * image.channels)
    throw Error("cannot encode PNG: malformed image");
  std::string out;
  if (!stbi_write_png_to_func(append_bytes, &out, image.width, image.height, image.channels,
                              image.pixels.data(), image.width * image.channels))
    throw Error("cannot encode PNG");
  return out;
}

void write_png(const std::string& path, const Image& image) { write_file_atomic(path, encode_png(image)); }

}  // namespace volspline::io
