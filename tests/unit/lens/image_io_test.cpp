// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/io/image_io.h"

using namespace volspline;

TEST_CASE("PNG round trip is exact for grey, RGB and RGBA") {
  for (int channels : {1, 3, 4}) {
    Image img{7, 5, channels, {}};
    for (int i = 0; i < 7 * 5 * channels; ++i) img.pixels.push_back(static_cast<std::uint8_t>(i * 37 % 256));
    const Image back = io::decode_image(io::encode_png(img), "mem.png");
    CHECK(back.width == 7);
    CHECK(back.height == 5);
    CHECK(back.channels == channels);
    CHECK(back.pixels == img.pixels);
  }
}

TEST_CASE("shared sample images decode") {
  const Image cam = io::read_image(std::string(VOLSPLINE_SHARED_DATA) + "/images/camera.png");
  CHECK(cam.width == 512);
  CHECK(cam.height == 512);
  CHECK(cam.channels == 1);
}

TEST_CASE("unreadable images name the file") {
  CHECK_THROWS_WITH_AS(io::decode_image("not an image", "bad.png"), doctest::Contains("'bad.png': not a readable"), Error);
  CHECK_THROWS_WITH_AS(io::decode_image("", "empty.png"), doctest::Contains("'empty.png': empty file"), Error);
  CHECK_THROWS_WITH_AS(io::read_image("/no/such/file.png"), doctest::Contains("/no/such/file.png"), Error);
  CHECK_THROWS_AS(io::encode_png(Image{}), Error);
}
