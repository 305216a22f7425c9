// SPDX-License-Identifier: MIT
// libFuzzer target: decode_image on arbitrary bytes (PNG and JPEG, through the header and DHT
// checks that run before stb) must return an image or throw volspline::Error; anything else
// (crash, sanitizer report, other exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/common/error.h"
#include "core/io/image_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  volspline::io::ImageLimits limits;
  limits.max_pixels = std::int64_t{1} << 22;  // keeps each run within the fuzzer's memory limit
  try {
    const auto image = volspline::io::decode_image(bytes, "fuzz.img", limits);
    if (image.width < 1 || image.height < 1 || image.channels < 1 || image.channels > 4 ||
        image.pixels.size() != std::size_t(image.width) * image.height * image.channels ||
        std::int64_t(image.width) * image.height > limits.max_pixels)
      __builtin_trap();
  } catch (const volspline::Error&) {
  }
  return 0;
}
