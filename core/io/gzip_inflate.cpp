// SPDX-License-Identifier: MIT
#include "core/io/gzip_inflate.h"

#include <climits>
#include <cstdint>

#include "core/common/error.h"

#ifdef VOLSPLINE_HAVE_ZLIB
#include <zlib.h>
#endif

namespace volspline::io {

namespace {

// Deflate's largest expansion (258-byte matches of 2 bits each), with room for the headers.
constexpr std::uint64_t kMaxRatio = 1032;
constexpr std::uint64_t kSlack = 1024;

}  // namespace

bool gzip_available() {
#ifdef VOLSPLINE_HAVE_ZLIB
  return true;
#else
  return false;
#endif
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
  (void)data;
  (void)size;
  (void)expected;
  throw Error(name + ": gzip encoding not supported (volspline is built without zlib)");
#endif
}

}  // namespace volspline::io
