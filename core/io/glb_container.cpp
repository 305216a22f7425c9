// SPDX-License-Identifier: MIT
#include "core/io/glb_container.h"

#include <algorithm>
#include <cstdint>
#include <limits>

namespace volspline::io {

namespace {

void append_u32(std::string& out, std::uint32_t x) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((x >> (8 * i)) & 0xff));
}

}  // namespace

std::string glb_container(std::string json, std::string bin) {
  while (json.size() % 4) json.push_back(' ');
  while (bin.size() % 4) bin.push_back('\0');
  std::string out;
  out.reserve(12 + 8 + json.size() + 8 + bin.size());
  append_u32(out, 0x46546C67);  // "glTF"
  append_u32(out, 2);
  append_u32(out, static_cast<std::uint32_t>(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size())));
  append_u32(out, static_cast<std::uint32_t>(json.size()));
  append_u32(out, 0x4E4F534A);  // "JSON"
  out += json;
  if (!bin.empty()) {
    append_u32(out, static_cast<std::uint32_t>(bin.size()));
    append_u32(out, 0x004E4942);  // "BIN\0"
    out += bin;
  }
  return out;
}

std::size_t append_glb_bytes(std::string& bin, const void* data, std::size_t bytes) {
  const std::size_t begin = bin.size();
  if (bytes > 0) bin.append(static_cast<const char*>(data), bytes);
  while (bin.size() % 4) bin.push_back('\0');
  return begin;
}

nlohmann::ordered_json glb_vec3_bound(const std::vector<float>& xyz, bool upper) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (int d = 0; d < 3; ++d) {
    float v = upper ? -std::numeric_limits<float>::max() : std::numeric_limits<float>::max();
    for (std::size_t i = d; i < xyz.size(); i += 3) v = upper ? std::max(v, xyz[i]) : std::min(v, xyz[i]);
    out.push_back(v);
  }
  return out;
}

}  // namespace volspline::io
