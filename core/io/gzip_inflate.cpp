// SPDX-License-Identifier: MIT
#include "core/io/gzip_inflate.h"

#include <climits>
#include <cstdint>

#include "core/common/error.h"

#ifdef VOLSPLINE_HAVE_ZLIB
#include <zlib.h>
#else
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
#endif

namespace volspline::io {

namespace {

// Deflate's largest expansion (258-byte matches of 2 bits each), with room for the headers.
constexpr std::uint64_t kMaxRatio = 1032;
constexpr std::uint64_t kSlack = 1024;

#ifndef VOLSPLINE_HAVE_ZLIB
// Size of a gzip member header (RFC 1952 §2.3): 10 bytes, then the optional extra field, name,
// comment and header CRC that FLG announces.
std::size_t gzip_header_size(const unsigned char* bytes, std::size_t size, const std::string& name) {
  if (bytes[2] != 8) throw Error(name + ": corrupt gzip data (unknown compression method)");
  const unsigned flags = bytes[3];
  std::size_t pos = 10;
  if (flags & 4) {
    if (pos + 2 > size) throw Error(name + ": truncated gzip header");
    pos += 2 + (bytes[pos] | bytes[pos + 1] << 8);
  }
  for (unsigned bit : {8u, 16u})
    if (flags & bit) {
      while (pos < size && bytes[pos] != 0) ++pos;
      ++pos;
    }
  if (flags & 2) pos += 2;
  if (pos > size) throw Error(name + ": truncated gzip header");
  return pos;
}

std::uint32_t crc32_of(const std::string& bytes) {
  std::uint32_t table[256];
  for (std::uint32_t n = 0; n < 256; ++n) {
    std::uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
    table[n] = c;
  }
  std::uint32_t crc = 0xffffffffu;
  for (unsigned char b : bytes) crc = table[(crc ^ b) & 0xff] ^ (crc >> 8);
  return crc ^ 0xffffffffu;
}

std::uint32_t adler32_of(const std::string& bytes) {
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : bytes) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  return b << 16 | a;
}

// stb's inflate into out[0, room); -1 on corrupt or truncated data or too little room.
int stb_inflate(std::string& out, std::size_t room, const char* data, std::size_t size) {
  out.assign(room, '\0');
  return stbi_zlib_decode_noheader_buffer(out.data(), static_cast<int>(room), data, static_cast<int>(size));
}
#endif

}  // namespace

bool gzip_available() { return true; }

std::size_t gzip_stated_size(const char* data, std::size_t size, const std::string& name) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(data);
  if (size < 18 || bytes[0] != 0x1f || bytes[1] != 0x8b) throw Error(name + ": not gzip data");
  const unsigned char* t = bytes + size - 4;
  return static_cast<std::size_t>(t[0] | t[1] << 8 | t[2] << 16 | std::uint32_t{t[3]} << 24);
}

std::string gzip_inflate(const char* data, std::size_t size, std::size_t expected, const std::string& name) {
#ifdef VOLSPLINE_HAVE_ZLIB
  if (static_cast<std::uint64_t>(expected) > kMaxRatio * size + kSlack)
    throw Error(name + ": truncated gzip data: " + std::to_string(size) + " compressed bytes cannot hold " +
                std::to_string(expected) + " bytes of samples");
  if (size > UINT_MAX || expected > UINT_MAX)
    throw Error(name + ": gzip data or samples over 4 GiB are not supported");
  std::string out(expected, '\0');
  z_stream stream{};
  if (inflateInit2(&stream, 15 + 32) != Z_OK)  // 15 + 32: a gzip or zlib header, detected
    throw Error(name + ": cannot start gzip decoding");
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data));
  stream.avail_in = static_cast<uInt>(size);
  stream.next_out = reinterpret_cast<Bytef*>(out.data());
  stream.avail_out = static_cast<uInt>(expected);
  // One call with all input and all room: the stream ends (good), or needs room it does not
  // have (oversized), or input it does not have (truncated), or is corrupt.
  const int status = inflate(&stream, Z_FINISH);
  const std::size_t produced = expected - stream.avail_out;
  const bool input_left = stream.avail_in > 0;
  const std::string message = stream.msg ? stream.msg : "";
  inflateEnd(&stream);
  if (status == Z_STREAM_END && produced == expected) return out;
  if (status == Z_STREAM_END)
    throw Error(name + ": truncated data: gzip data decompresses to " + std::to_string(produced) +
                " bytes, expected " + std::to_string(expected));
  if (status == Z_BUF_ERROR && produced == expected && input_left)
    throw Error(name + ": gzip data decompresses to more than the " + std::to_string(expected) +
                " bytes the header describes");
  if (status == Z_BUF_ERROR)
    throw Error(name + ": truncated gzip data (" + std::to_string(produced) + " of " + std::to_string(expected) +
                " bytes decoded)");
  throw Error(name + ": corrupt gzip data" + (message.empty() ? std::string() : " (" + message + ")"));
#else
  // No zlib (the WebAssembly build: Debian's emscripten 3.1.6 cannot fetch its zlib port offline):
  // stb_image's inflate, with the stream's checksum and size checked here, as stb checks neither.
  if (static_cast<std::uint64_t>(expected) > kMaxRatio * size + kSlack)
    throw Error(name + ": truncated gzip data: " + std::to_string(size) + " compressed bytes cannot hold " +
                std::to_string(expected) + " bytes of samples");
  if (size > INT_MAX / 2 || expected > INT_MAX / 2)
    throw Error(name + ": gzip data or samples over 1 GiB are not supported in this build");
  const auto* bytes = reinterpret_cast<const unsigned char*>(data);
  std::size_t begin = 0, end = 0;
  bool gzip = false;
  if (size >= 18 && bytes[0] == 0x1f && bytes[1] == 0x8b) {
    gzip = true;
    begin = gzip_header_size(bytes, size, name);
    end = size - 8;
  } else if (size >= 6 && (bytes[0] & 0x0f) == 8 && ((bytes[0] << 8) | bytes[1]) % 31 == 0) {
    begin = 2;
    end = size - 4;
  } else {
    throw Error(name + ": corrupt gzip data (neither a gzip nor a zlib header)");
  }
  if (begin > end) throw Error(name + ": truncated gzip data");
  std::string out;
  // One byte of room past `expected` tells data of the right size from oversized data. stb is
  // given the trailer too: its decoder fails when fewer than 16 bits follow the last code.
  int produced = stb_inflate(out, expected + 1, data + begin, size - begin);
  if (produced < 0) {
    std::string probe;
    if (stb_inflate(probe, 2 * expected + 65536, data + begin, size - begin) > static_cast<int>(expected))
      throw Error(name + ": gzip data decompresses to more than the " + std::to_string(expected) +
                  " bytes the header describes");
    throw Error(name + ": corrupt or truncated gzip data");
  }
  const auto got = static_cast<std::size_t>(produced);
  if (got > expected)
    throw Error(name + ": gzip data decompresses to more than the " + std::to_string(expected) +
                " bytes the header describes");
  out.resize(got);
  const unsigned char* tail = bytes + end;
  const std::uint32_t stated = gzip ? (tail[0] | tail[1] << 8 | tail[2] << 16 | std::uint32_t{tail[3]} << 24)
                                    : (std::uint32_t{tail[0]} << 24 | tail[1] << 16 | tail[2] << 8 | tail[3]);
  if (stated != (gzip ? crc32_of(out) : adler32_of(out))) throw Error(name + ": corrupt gzip data (checksum mismatch)");
  if (got < expected)
    throw Error(name + ": truncated data: gzip data decompresses to " + std::to_string(got) + " bytes, expected " +
                std::to_string(expected));
  return out;
#endif
}

}  // namespace volspline::io
