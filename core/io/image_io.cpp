// SPDX-License-Identifier: MIT
#include "core/io/image_io.h"

#include <climits>
#include <cstdint>
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

std::string failure_reason() {
  const char* reason = stbi_failure_reason();
  return reason && *reason ? reason : "no reason given";
}

struct ImageHeader {
  bool png = false;
  int width = 0, height = 0;
};

std::uint32_t big_endian32(const std::string& bytes, std::size_t at) {
  return std::uint32_t(std::uint8_t(bytes[at])) << 24 | std::uint32_t(std::uint8_t(bytes[at + 1])) << 16 |
         std::uint32_t(std::uint8_t(bytes[at + 2])) << 8 | std::uint32_t(std::uint8_t(bytes[at + 3]));
}

int big_endian16(const std::string& bytes, std::size_t at) {
  return int(std::uint8_t(bytes[at])) << 8 | int(std::uint8_t(bytes[at + 1]));
}

// The Huffman tables of one DHT segment (ITU T.81 §B.2.4.2): a class/id byte, 16 counts and as
// many symbols as the counts sum to, at most 256 per table (stb 2.27 writes past its tables
// otherwise). The walk is the one stb makes over the segment.
// `defined` gets bit 4·class + id of every table.
void check_dht(const std::string& bytes, std::size_t begin, std::size_t end, const std::string& name, int& defined) {
  std::size_t at = begin;
  while (at < end) {
    if (end - at < 17) throw Error("'" + name + "': corrupt JPEG: a Huffman table (DHT) is cut short");
    const int id = std::uint8_t(bytes[at]);
    if ((id >> 4) > 1 || (id & 15) > 3) throw Error("'" + name + "': corrupt JPEG: bad Huffman table (DHT) id");
    defined |= 1 << (4 * (id >> 4) + (id & 15));
    std::size_t symbols = 0;
    for (int i = 1; i <= 16; ++i) symbols += std::uint8_t(bytes[at + std::size_t(i)]);
    if (symbols > 256)
      throw Error("'" + name + "': corrupt JPEG: a Huffman table (DHT) declares " + std::to_string(symbols) +
                  " codes, more than 256");
    if (end - at - 17 < symbols) throw Error("'" + name + "': corrupt JPEG: a Huffman table (DHT) is cut short");
    at += 17 + symbols;
  }
}

// A scan header (ITU T.81 §B.2.3): every Huffman table the scan decodes with is defined (stb
// 2.27 decodes with an undefined table's uninitialized memory). A progressive scan decodes
// with its DC tables when it starts at coefficient 0 (first pass only), else its AC tables.
void check_sos(const std::string& bytes, std::size_t begin, std::size_t end, const std::string& name, bool progressive,
               int defined) {
  if (end - begin < 1) throw Error("'" + name + "': corrupt JPEG: empty scan header (SOS)");
  const std::size_t components = std::uint8_t(bytes[begin]);
  if (components < 1 || components > 4 || end - begin != 1 + 2 * components + 3)
    throw Error("'" + name + "': corrupt JPEG: bad scan header (SOS) length");
  const int start = std::uint8_t(bytes[begin + 1 + 2 * components]);
  const int high = std::uint8_t(bytes[begin + 3 + 2 * components]) >> 4;
  const bool uses_dc = !progressive || (start == 0 && high == 0), uses_ac = !progressive || start > 0;
  for (std::size_t c = 0; c < components; ++c) {
    const int tables = std::uint8_t(bytes[begin + 2 + 2 * c]);
    const int dc = tables >> 4, ac = tables & 15;
    if ((uses_dc && (dc > 3 || !(defined >> dc & 1))) || (uses_ac && (ac > 3 || !(defined >> (4 + ac) & 1))))
      throw Error("'" + name + "': corrupt JPEG: a scan uses a Huffman table that no DHT segment defines");
  }
}

// JPEG markers (ITU T.81 §B.1.1): walks every segment, and the entropy-coded data after each
// scan to the next marker, so DHT segments between progressive scans are checked too.
ImageHeader read_jpeg_header(const std::string& bytes, const std::string& name) {
  ImageHeader header;
  int defined_tables = 0;
  bool progressive = false;
  std::size_t at = 2;
  bool has_scan = false;
  while (true) {
    // Find the next marker: 0xFF followed by a code (0xFF fill bytes may repeat); inside
    // entropy-coded data 0xFF 0x00 is a stuffed byte and 0xFF 0xD0..0xD7 are restart markers.
    while (at < bytes.size() && std::uint8_t(bytes[at]) != 0xFF) ++at;
    while (at < bytes.size() && std::uint8_t(bytes[at]) == 0xFF) ++at;
    if (at >= bytes.size()) break;
    const int marker = std::uint8_t(bytes[at++]);
    if (marker == 0x00 || (marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) continue;
    if (marker == 0xD9) break;  // EOI
    if (marker == 0xD8) continue;
    if (bytes.size() - at < 2)
      throw Error("'" + name + "': truncated JPEG (the file ends inside a marker segment)");
    const std::size_t length = std::size_t(big_endian16(bytes, at));
    if (length < 2) throw Error("'" + name + "': corrupt JPEG: marker segment of length " + std::to_string(length));
    if (bytes.size() - at < length)
      throw Error("'" + name + "': truncated JPEG (a marker segment runs " + std::to_string(length - (bytes.size() - at)) +
                  " bytes past the end of the file)");
    const std::size_t begin = at + 2, end = at + length;
    if (marker == 0xC4) check_dht(bytes, begin, end, name, defined_tables);
    if (marker == 0xC2) progressive = true;
    if (marker == 0xDA) check_sos(bytes, begin, end, name, progressive, defined_tables);
    const bool frame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame && end - begin >= 5 && header.width == 0) {
      header.height = big_endian16(bytes, begin + 1);
      header.width = big_endian16(bytes, begin + 3);
    }
    if (marker == 0xDA) has_scan = true;
    at = end;
  }
  if (!has_scan) throw Error("'" + name + "': truncated JPEG (no image data: the file ends before the first scan)");
  return header;
}

ImageHeader read_image_header(const std::string& bytes, const std::string& name) {
  static const char kPng[8] = {'\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n'};
  if (bytes.size() >= 2 && std::uint8_t(bytes[0]) == 0xFF && std::uint8_t(bytes[1]) == 0xD8)
    return read_jpeg_header(bytes, name);
  if (bytes.size() >= 8 && bytes.compare(0, 8, kPng, 8) == 0) {
    // The first chunk is IHDR (PNG §11.2.2): width and height, big-endian.
    if (bytes.size() < 33) throw Error("'" + name + "': truncated PNG (the file ends inside its IHDR header)");
    if (bytes.compare(12, 4, "IHDR") != 0) throw Error("'" + name + "': corrupt PNG: the first chunk is not IHDR");
    ImageHeader header;
    header.png = true;
    const std::uint32_t width = big_endian32(bytes, 16), height = big_endian32(bytes, 20);
    if (width == 0 || height == 0 || width > 0x7FFFFFFFu || height > 0x7FFFFFFFu)
      throw Error("'" + name + "': corrupt PNG: " + std::to_string(width) + " x " + std::to_string(height) + " pixels");
    header.width = int(width);
    header.height = int(height);
    return header;
  }
  throw Error("'" + name + "': not a PNG or JPEG image (no PNG signature or JPEG start marker)");
}

// The PNG checked chunk by chunk and without its empty IDAT chunks. stb_image 2.27 grows its
// data buffer to a chunk's declared length before it checks that the file holds those bytes
// (gigabytes for a 100-byte file), and copies an empty IDAT from a buffer it has not allocated
// yet (memcpy from null). So a chunk that runs past the end of the file is refused here, and an
// empty IDAT, which adds no data (PNG §11.2.4), is dropped. The walk ends at IEND.
std::string checked_png(const std::string& bytes, const std::string& name) {
  std::string out;
  std::size_t at = 8, copied = 0;
  while (at < bytes.size()) {
    // stb reads a chunk from its 8-byte header on, so a chunk cut short anywhere (even in its
    // CRC) is refused here rather than handed on.
    if (bytes.size() - at < 12)
      throw Error("'" + name + "': truncated PNG (the file ends inside a chunk's header or CRC)");
    const std::uint32_t length = big_endian32(bytes, at);
    if (length > bytes.size() - at - 12)
      throw Error("'" + name + "': truncated PNG (a chunk of " + std::to_string(length) +
                  " bytes runs past the end of the file)");
    if (length == 0 && bytes.compare(at + 4, 4, "IDAT") == 0) {
      out.append(bytes, copied, at - copied);
      copied = at + 12;
    }
    const bool end = bytes.compare(at + 4, 4, "IEND") == 0;
    at += 12 + static_cast<std::size_t>(length);
    if (end) break;
  }
  if (copied == 0) return bytes;
  out.append(bytes, copied, std::string::npos);
  return out;
}

}  // namespace

Image decode_image(const std::string& bytes, const std::string& name, const ImageLimits& limits) {
  if (bytes.empty()) throw Error("'" + name + "': empty file, expected a PNG or JPEG image");
  if (bytes.size() > static_cast<std::size_t>(INT_MAX)) throw Error("'" + name + "': file too large");
  // The header is read here first: the size limit holds before stb allocates, JPEG tables that
  // stb 2.27 would write out of bounds are refused, and failures get a message of their kind.
  const ImageHeader header = read_image_header(bytes, name);
  if (static_cast<std::int64_t>(header.width) * header.height > limits.max_pixels)
    throw Error("'" + name + "': " + (header.png ? "PNG" : "JPEG") + " of " + std::to_string(header.width) + " x " +
                std::to_string(header.height) + " pixels is above the limit `max_pixels` = " +
                std::to_string(limits.max_pixels));
  const char* kind = header.png ? "PNG" : "JPEG";
  int width = 0, height = 0, channels_in_file = 0;
  const std::string cleaned = header.png ? checked_png(bytes, name) : std::string();
  const std::string& input = header.png ? cleaned : bytes;
  const auto* data = reinterpret_cast<const stbi_uc*>(input.data());
  if (!stbi_info_from_memory(data, static_cast<int>(input.size()), &width, &height, &channels_in_file))
    throw Error("'" + name + "': cannot read the " + kind + " header (" + failure_reason() + ")");
  // Grey+alpha has no 8-bit interchange layout of its own here, so it is widened to RGBA.
  const int channels = channels_in_file == 2 ? 4 : channels_in_file;
  stbi_uc* pixels = stbi_load_from_memory(data, static_cast<int>(input.size()), &width, &height,
                                          &channels_in_file, channels);
  if (!pixels) throw Error("'" + name + "': cannot decode the " + kind + " data (" + failure_reason() + ")");
  Image image;
  image.width = width;
  image.height = height;
  image.channels = channels;
  image.pixels.assign(pixels, pixels + static_cast<std::size_t>(width) * height * channels);
  stbi_image_free(pixels);
  return image;
}

Image read_image(const std::string& path, const ImageLimits& limits) {
  return decode_image(read_file_bytes(path), path, limits);
}

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
