// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/io/image_io.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STBI_WRITE_NO_STDIO
#include <stb_image_write.h>

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
  CHECK_THROWS_WITH_AS(io::decode_image("not an image", "bad.png"), doctest::Contains("'bad.png': not a PNG or JPEG image"), Error);
  CHECK_THROWS_WITH_AS(io::decode_image("", "empty.png"), doctest::Contains("'empty.png': empty file"), Error);
  CHECK_THROWS_WITH_AS(io::read_image("/no/such/file.png"), doctest::Contains("/no/such/file.png"), Error);
  CHECK_THROWS_AS(io::encode_png(Image{}), Error);
}

namespace {

void append_encoded(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}

// A 16 × 8 RGB gradient as a baseline JPEG (stb's writer: one DQT, one DHT segment per table).
std::string gradient_jpeg() {
  std::string pixels(16 * 8 * 3, '\0');
  for (int i = 0; i < 16 * 8; ++i) pixels[3 * i] = char(i * 2), pixels[3 * i + 1] = char(255 - i), pixels[3 * i + 2] = 90;
  std::string out;
  REQUIRE(stbi_write_jpg_to_func(append_encoded, &out, 16, 8, 3, pixels.data(), 90));
  return out;
}

std::string image_error(const std::string& bytes, const io::ImageLimits& limits = {}) {
  try {
    io::decode_image(bytes, "x.img", limits);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// PNG signature and an IHDR chunk of width × height (CRC left zero: the size is refused first).
std::string png_header(std::uint32_t width, std::uint32_t height) {
  std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
  for (std::uint32_t v : {width, height})
    for (int s = 24; s >= 0; s -= 8) png += char((v >> s) & 0xFF);
  png += std::string("\x08\x02\0\0\0\0\0\0\0", 9);
  return png;
}

}  // namespace

TEST_CASE("a JPEG decodes to its size") {
  const Image image = io::decode_image(gradient_jpeg(), "g.jpg");
  CHECK(image.width == 16);
  CHECK(image.height == 8);
  CHECK(image.channels == 3);
}

TEST_CASE("a JPEG Huffman table with more than 256 codes is refused before stb decodes it") {
  std::string jpeg = gradient_jpeg();
  const std::size_t dht = jpeg.find("\xFF\xC4");
  REQUIRE(dht != std::string::npos);
  // Counts of the first table: 16 × 20 = 320 codes (stb 2.27 writes past its 257-entry table).
  for (int i = 0; i < 16; ++i) jpeg[dht + 5 + std::size_t(i)] = 20;
  CHECK(image_error(jpeg) == "'x.img': corrupt JPEG: a Huffman table (DHT) declares 320 codes, more than 256");
  // Also in a DHT that only follows the first scan (progressive files carry them there).
  std::string later = gradient_jpeg();
  const std::size_t eoi = later.rfind("\xFF\xD9");
  REQUIRE(eoi != std::string::npos);
  std::string bad_dht("\xFF\xC4\x00\x23\x10", 5);
  bad_dht += std::string(16, '\x11');  // 16 × 17 = 272 codes
  bad_dht += std::string(14, '\0');
  later.insert(eoi, bad_dht);
  CHECK(image_error(later).find("declares 272 codes, more than 256") != std::string::npos);
}

TEST_CASE("a JPEG scan that uses an undefined Huffman table is refused before stb decodes it") {
  std::string jpeg = gradient_jpeg();
  const std::size_t sos = jpeg.find("\xFF\xDA");
  REQUIRE(sos != std::string::npos);
  // First component's selectors: DC table 1, AC table 2 (stb's writer defines tables 0 and 1).
  jpeg[sos + 6] = 0x12;
  CHECK(image_error(jpeg) == "'x.img': corrupt JPEG: a scan uses a Huffman table that no DHT segment defines");
}

TEST_CASE("truncated, corrupt, oversize and unknown images get messages of their own") {
  const std::string jpeg = gradient_jpeg();
  CHECK(image_error(jpeg.substr(0, 40)).find("truncated JPEG") != std::string::npos);
  CHECK(image_error(jpeg.substr(0, 2)) == "'x.img': truncated JPEG (no image data: the file ends before the first scan)");
  CHECK(image_error(png_header(20000, 20000)) ==
        "'x.img': PNG of 20000 x 20000 pixels is above the limit `max_pixels` = 67108864");
  io::ImageLimits small;
  small.max_pixels = 100;
  CHECK(image_error(jpeg, small) == "'x.img': JPEG of 16 x 8 pixels is above the limit `max_pixels` = 100");
  CHECK(image_error(png_header(20000, 20000).substr(0, 20)) == "'x.img': truncated PNG (the file ends inside its IHDR header)");
  CHECK(image_error(png_header(4, 4)).find("cannot decode the PNG data") != std::string::npos);
  // An empty IDAT whose CRC is cut short (stb would copy it from a null buffer).
  CHECK(image_error(png_header(8, 6) + std::string("\0\0\0\0IDAT\x42\x60\x82", 11)) ==
        "'x.img': truncated PNG (the file ends inside a chunk's header or CRC)");
  CHECK(image_error("GIF89a......") == "'x.img': not a PNG or JPEG image (no PNG signature or JPEG start marker)");
  CHECK(image_error("") == "'x.img': empty file, expected a PNG or JPEG image");
}
