// SPDX-License-Identifier: MIT
#include "core/io/vti_format.h"

#include <cstdint>
#include <cstring>
#include <map>
#include <vector>

#include "core/common/error.h"
#include "core/io/gzip_inflate.h"
#include "core/io/volume_data.h"
#include "core/io/volume_header_text.h"

namespace volspline::io {

namespace {

using volume::SampleType;
using namespace volume_text;

// One XML start tag: its name, attributes and where its content starts.
struct Tag {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::size_t content_begin = 0;
  bool self_closing = false;
};

// Reads the start or end tag at or after pos (skipping <?...?>, comments and text); an end tag
// has a name starting with '/'. Returns false at the end of input.
bool next_tag(const std::string& xml, std::size_t& pos, Tag& tag, const std::string& name) {
  while (true) {
    const std::size_t open = xml.find('<', pos);
    if (open == std::string::npos) return false;
    if (xml.compare(open, 4, "<!--") == 0) {
      const std::size_t end = xml.find("-->", open);
      if (end == std::string::npos) throw Error(name + ": unterminated XML comment");
      pos = end + 3;
      continue;
    }
    const std::size_t close = xml.find('>', open);
    if (close == std::string::npos) throw Error(name + ": unterminated XML tag");
    if (xml[open + 1] == '?' || xml[open + 1] == '!') {
      pos = close + 1;
      continue;
    }
    tag = Tag{};
    std::size_t p = open + 1;
    while (p < close && !std::isspace(static_cast<unsigned char>(xml[p])) && xml[p] != '/' && xml[p] != '>') ++p;
    if (xml[open + 1] == '/') {
      tag.name = "/" + trim(xml.substr(open + 2, close - open - 2));
      tag.content_begin = close + 1;
      pos = close + 1;
      return true;
    }
    tag.name = xml.substr(open + 1, p - open - 1);
    tag.self_closing = xml[close - 1] == '/';
    while (p < close) {
      while (p < close && (std::isspace(static_cast<unsigned char>(xml[p])) || xml[p] == '/')) ++p;
      if (p >= close) break;
      const std::size_t eq = xml.find('=', p);
      if (eq == std::string::npos || eq > close) throw Error(name + ": bad XML attribute in <" + tag.name + ">");
      const std::string key = trim(xml.substr(p, eq - p));
      std::size_t q = eq + 1;
      while (q < close && std::isspace(static_cast<unsigned char>(xml[q]))) ++q;
      const char quote = xml[q];
      if (quote != '"' && quote != '\'') throw Error(name + ": unquoted XML attribute '" + key + "'");
      const std::size_t end = xml.find(quote, q + 1);
      if (end == std::string::npos || end > close) throw Error(name + ": unterminated XML attribute '" + key + "'");
      tag.attributes[key] = xml.substr(q + 1, end - q - 1);
      p = end + 1;
    }
    tag.content_begin = close + 1;
    pos = close + 1;
    return true;
  }
}

std::string attribute(const Tag& tag, const std::string& key, const std::string& name) {
  const auto it = tag.attributes.find(key);
  if (it == tag.attributes.end()) throw Error(name + ": <" + tag.name + "> has no " + key + " attribute");
  return it->second;
}

std::string attribute_or(const Tag& tag, const std::string& key, const std::string& fallback) {
  const auto it = tag.attributes.find(key);
  return it == tag.attributes.end() ? fallback : it->second;
}

std::vector<double> reals(const std::string& text, std::size_t count, const std::string& name, const std::string& what) {
  const auto words = split_words(text);
  if (words.size() != count)
    throw Error(name + ": " + what + " needs " + std::to_string(count) + " values, got " + std::to_string(words.size()));
  std::vector<double> values;
  for (const auto& w : words) values.push_back(parse_real(w, name, what));
  return values;
}

// Extents: `count` integers within ±2^30 (so their differences fit an int).
std::vector<long long> extent_values(const std::string& text, std::size_t count, const std::string& name, const std::string& what) {
  const auto words = split_words(text);
  if (words.size() != count)
    throw Error(name + ": " + what + " needs " + std::to_string(count) + " values, got " + std::to_string(words.size()));
  std::vector<long long> values;
  for (const auto& w : words) {
    const long long v = parse_integer(w, name, what);
    if (v < -(1LL << 30) || v > (1LL << 30)) throw Error(name + ": " + what + " value " + w + " is out of range");
    values.push_back(v);
  }
  return values;
}

SampleType vti_type(const std::string& text, const std::string& name) {
  return volume_data::sample_type_named(text, {"UInt8", "Int8", "UInt16", "Int16", "UInt32", "Int32", "Float32", "Float64"},
                                        text, name);
}

// Base64 (RFC 4648) decoded in 4-character groups, so that separately encoded streams written
// one after another (VTK's compressed header, then its blocks) decode as one.
std::string base64_decode(const char* text, std::size_t size, const std::string& name) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::string out;
  out.reserve(size / 4 * 3);
  int group[4];
  int count = 0, pad = 0;
  for (std::size_t i = 0; i < size; ++i) {
    const char c = text[i];
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    if (c == '=') {
      group[count++] = 0;
      ++pad;
    } else {
      const int v = value(c);
      if (v < 0 || pad > 0) throw Error(name + ": bad base64 data");
      group[count++] = v;
    }
    if (count == 4) {
      const std::uint32_t bits = static_cast<std::uint32_t>(group[0]) << 18 | group[1] << 12 | group[2] << 6 | group[3];
      const char bytes[3] = {static_cast<char>(bits >> 16), static_cast<char>(bits >> 8 & 255), static_cast<char>(bits & 255)};
      if (pad > 2) throw Error(name + ": bad base64 padding");
      out.append(bytes, 3 - pad);
      count = 0;
      pad = 0;
    }
  }
  if (count != 0) throw Error(name + ": truncated base64 data");
  return out;
}

// The file-level settings that decide how an array's bytes are laid out.
struct ArrayLayout {
  bool big_endian = false;
  int header_bytes = 4;  // UInt32 or UInt64
  bool zlib = false;
};

std::uint64_t read_header_word(const std::string& bytes, std::size_t offset, const ArrayLayout& e, const std::string& name) {
  if (offset + e.header_bytes > bytes.size()) throw Error(name + ": truncated DataArray header");
  std::uint64_t value = 0;
  for (int k = 0; k < e.header_bytes; ++k) {
    const auto byte = static_cast<unsigned char>(bytes[offset + (e.big_endian ? k : e.header_bytes - 1 - k)]);
    value = value << 8 | byte;
  }
  return value;
}

// Samples from an array's binary form: [byte count][data], or with zlib
// [blocks][block size][last block size][compressed sizes...][blocks...]. `decode` turns the
// stored text into bytes (base64) or is null for raw bytes; with base64 the header and the
// blocks of compressed data are separate streams, and must be decoded before their sizes are known.
std::string array_bytes(const std::string& stored, const ArrayLayout& e, std::uint64_t expected, const std::string& name) {
  if (!e.zlib) {
    const std::uint64_t size = read_header_word(stored, 0, e, name);
    if (size != expected)
      throw Error(name + ": DataArray holds " + std::to_string(size) + " bytes, the extent needs " + std::to_string(expected));
    if (stored.size() - e.header_bytes < size) throw Error(name + ": truncated DataArray data");
    return stored.substr(static_cast<std::size_t>(e.header_bytes), static_cast<std::size_t>(size));
  }
  const std::uint64_t blocks = read_header_word(stored, 0, e, name);
  const std::uint64_t block_size = read_header_word(stored, e.header_bytes, e, name);
  const std::uint64_t last_size = read_header_word(stored, 2 * e.header_bytes, e, name);
  if (blocks > stored.size() / e.header_bytes) throw Error(name + ": truncated DataArray header");
  const std::uint64_t total = blocks == 0 ? 0 : (blocks - 1) * block_size + (last_size == 0 ? block_size : last_size);
  if (total != expected)
    throw Error(name + ": DataArray holds " + std::to_string(total) + " bytes, the extent needs " + std::to_string(expected));
  std::size_t pos = static_cast<std::size_t>((3 + blocks) * e.header_bytes);
  std::string out;
  out.reserve(static_cast<std::size_t>(total));
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t compressed = read_header_word(stored, static_cast<std::size_t>((3 + b) * e.header_bytes), e, name);
    const std::uint64_t plain = b + 1 == blocks && last_size != 0 ? last_size : block_size;
    if (compressed > stored.size() - std::min<std::size_t>(pos, stored.size()))
      throw Error(name + ": truncated zlib block " + std::to_string(b) + " of the DataArray");
    out += gzip_inflate(stored.data() + pos, static_cast<std::size_t>(compressed), static_cast<std::size_t>(plain), name);
    pos += static_cast<std::size_t>(compressed);
  }
  return out;
}

// Base64 text of a header-then-blocks array: decodes the header first to learn the blocks' sizes.
std::string decode_base64_array(const char* text, std::size_t size, const ArrayLayout& e, const std::string& name) {
  if (!e.zlib) return base64_decode(text, size, name);
  // The header is its own base64 stream: 4 characters per 3 bytes, padded.
  const auto stream_chars = [](std::size_t bytes) { return (bytes + 2) / 3 * 4; };
  std::string compact;
  compact.reserve(size);
  for (std::size_t i = 0; i < size; ++i)
    if (!std::isspace(static_cast<unsigned char>(text[i]))) compact += text[i];
  const std::size_t first = stream_chars(static_cast<std::size_t>(e.header_bytes));
  if (compact.size() < first) throw Error(name + ": truncated DataArray header");
  const std::string count_bytes = base64_decode(compact.data(), first, name);
  const std::uint64_t blocks = read_header_word(count_bytes, 0, e, name);
  if (blocks > compact.size()) throw Error(name + ": truncated DataArray header");
  const std::size_t header_chars = stream_chars(static_cast<std::size_t>((3 + blocks) * e.header_bytes));
  if (compact.size() < header_chars) throw Error(name + ": truncated DataArray header");
  return base64_decode(compact.data(), header_chars, name) +
         base64_decode(compact.data() + header_chars, compact.size() - header_chars, name);
}

}  // namespace

volume::Volume parse_vti(const std::string& xml, const std::string& name, std::int64_t max_voxels) {
  std::size_t pos = 0;
  Tag tag;
  ArrayLayout encoding;
  volume_data::DataLayout layout;
  std::array<long long, 6> extent{};
  bool in_point_data = false, has_image = false, has_piece = false;
  std::string active;
  Tag chosen;
  bool has_array = false;
  std::size_t appended = std::string::npos;
  while (next_tag(xml, pos, tag, name)) {
    if (tag.name == "VTKFile") {
      if (attribute(tag, "type", name) != "ImageData")
        throw Error(name + ": not a VTK ImageData file (type '" + attribute(tag, "type", name) + "')");
      encoding.big_endian = attribute_or(tag, "byte_order", "LittleEndian") == "BigEndian";
      const std::string header = attribute_or(tag, "header_type", "UInt32");
      if (header != "UInt32" && header != "UInt64") throw Error(name + ": unsupported header_type '" + header + "'");
      encoding.header_bytes = header == "UInt64" ? 8 : 4;
      const std::string compressor = attribute_or(tag, "compressor", "");
      if (!compressor.empty() && compressor != "vtkZLibDataCompressor")
        throw Error(name + ": compressor '" + compressor + "' is not supported (write with zlib or no compression)");
      encoding.zlib = !compressor.empty();
    } else if (tag.name == "ImageData") {
      const auto whole = extent_values(attribute(tag, "WholeExtent", name), 6, name, "WholeExtent");
      for (int k = 0; k < 6; ++k) extent[k] = whole[k];
      const auto origin = reals(attribute_or(tag, "Origin", "0 0 0"), 3, name, "Origin");
      const auto spacing = reals(attribute_or(tag, "Spacing", "1 1 1"), 3, name, "Spacing");
      const auto direction = reals(attribute_or(tag, "Direction", "1 0 0 0 1 0 0 0 1"), 9, name, "Direction");
      Eigen::Matrix3d steps;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) steps(r, c) = direction[3 * r + c] * spacing[c];  // row-major, columns are axes
      for (int a = 0; a < 3; ++a)
        if (!(spacing[a] > 0)) throw Error(name + ": Spacing value " + std::to_string(spacing[a]) + " is not positive");
      volume_data::set_axes_from_steps(layout, steps, name, "Direction");
      for (int k = 0; k < 3; ++k) layout.origin[k] = origin[k];
      has_image = true;
    } else if (tag.name == "Piece") {
      if (has_piece) throw Error(name + ": ImageData with more than one Piece is not supported");
      const auto piece = extent_values(attribute_or(tag, "Extent", ""), 6, name, "Piece Extent");
      for (int k = 0; k < 6; ++k)
        if (piece[k] != extent[k])
          throw Error(name + ": a Piece that does not cover the WholeExtent is not supported");
      has_piece = true;
    } else if (tag.name == "PointData") {
      in_point_data = !tag.self_closing;
      active = attribute_or(tag, "Scalars", "");
    } else if (tag.name == "/PointData") {
      in_point_data = false;
    } else if (tag.name == "DataArray" && in_point_data) {
      const bool one_component = attribute_or(tag, "NumberOfComponents", "1") == "1";
      const bool named = !active.empty() && attribute_or(tag, "Name", "") == active;
      if (named || (!has_array && one_component && active.empty())) {
        if (!one_component) throw Error(name + ": the Scalars array '" + active + "' has more than one component");
        chosen = tag;
        has_array = true;
      }
    } else if (tag.name == "AppendedData") {
      const std::size_t underscore = xml.find('_', tag.content_begin);
      if (underscore == std::string::npos) throw Error(name + ": AppendedData has no '_' marker");
      appended = underscore + 1;
      chosen.attributes["appended_encoding"] = attribute_or(tag, "encoding", "raw");
      break;  // raw appended bytes may hold anything, '<' included
    }
  }
  if (!has_image) throw Error(name + ": no <ImageData> element");
  if (!has_piece) throw Error(name + ": no <Piece> element");
  if (!has_array) throw Error(name + ": no 1-component point data array");
  for (int a = 0; a < 3; ++a) {
    const long long size = extent[2 * a + 1] - extent[2 * a] + 1;
    if (size < 1 || size > (1 << 30)) throw Error(name + ": bad WholeExtent");
    layout.raw.dims[a] = static_cast<int>(size);
  }
  // Extents may start off 0: voxel (0, 0, 0) of the volume is extent index (x0, y0, z0).
  layout.origin += layout.direction * Eigen::Vector3d(extent[0] * layout.spacing.x(), extent[2] * layout.spacing.y(),
                                                      extent[4] * layout.spacing.z());
  layout.raw.type = vti_type(attribute(chosen, "type", name), name);
  layout.raw.big_endian = encoding.big_endian;
  volume_data::check_voxel_limit(layout.raw.dims, max_voxels, name);
  const std::uint64_t count = volume_data::checked_voxel_count(layout.raw.dims, name);
  const std::uint64_t expected = count * static_cast<std::uint64_t>(volume::sample_type_size(layout.raw.type));
  const std::string format = attribute_or(chosen, "format", "ascii");
  std::string data;
  if (format == "ascii") {
    const std::size_t end = xml.find('<', chosen.content_begin);
    layout.encoding = volume_data::Encoding::Ascii;
    return volume_data::decode_data(xml.substr(chosen.content_begin, end - chosen.content_begin), 0, layout, name);
  } else if (format == "binary") {
    const std::size_t end = xml.find('<', chosen.content_begin);
    if (end == std::string::npos) throw Error(name + ": unterminated DataArray");
    data = decode_base64_array(xml.data() + chosen.content_begin, end - chosen.content_begin, encoding, name);
  } else if (format == "appended") {
    if (appended == std::string::npos) throw Error(name + ": appended DataArray without <AppendedData>");
    const long long offset = parse_integer(attribute(chosen, "offset", name), name, "DataArray offset");
    if (offset < 0 || static_cast<std::uint64_t>(offset) > xml.size() - appended) throw Error(name + ": DataArray offset past the end");
    const std::size_t begin = appended + static_cast<std::size_t>(offset);
    if (chosen.attributes["appended_encoding"] == "base64") {
      std::size_t end = begin;
      while (end < xml.size() && xml[end] != '<' && xml[end] != '_') ++end;
      data = decode_base64_array(xml.data() + begin, end - begin, encoding, name);
    } else if (chosen.attributes["appended_encoding"] == "raw") {
      data = xml.substr(begin);
    } else {
      throw Error(name + ": unsupported AppendedData encoding '" + chosen.attributes["appended_encoding"] + "'");
    }
  } else {
    throw Error(name + ": unsupported DataArray format '" + format + "'");
  }
  const std::string samples = array_bytes(data, encoding, expected, name);
  return volume_data::decode_data(samples, 0, layout, name);
}

}  // namespace volspline::io
