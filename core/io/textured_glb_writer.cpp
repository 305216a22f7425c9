// SPDX-License-Identifier: MIT
#include "core/io/textured_glb_writer.h"

#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/common/error.h"

namespace volspline::io {

namespace {

template <class T>
std::size_t append_aligned(std::string& bin, const T* data, std::size_t bytes) {
  const std::size_t begin = bin.size();
  bin.append(reinterpret_cast<const char*>(data), bytes);
  while (bin.size() % 4) bin.push_back('\0');
  return begin;
}

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

std::string serialize_textured_glb(const TexturedPlane& plane) {
  const auto n = static_cast<std::size_t>(plane.positions.rows());
  const auto m = static_cast<std::size_t>(plane.triangles.rows());
  if (n == 0 || m == 0) throw Error("cannot write a textured GLB of an empty mesh");
  if (static_cast<std::size_t>(plane.texture.rows()) != n) throw Error("cannot write a textured GLB: texture rows differ from positions");
  if (plane.texture_width <= 0 || plane.texture_height <= 0 || plane.texture_png.empty())
    throw Error("cannot write a textured GLB without its texture image");
  std::vector<float> xyz, normal, uv;
  xyz.reserve(3 * n);
  float lo[3] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), 0};
  float hi[3] = {std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest(), 0};
  for (std::size_t v = 0; v < n; ++v) {
    const float p[3] = {static_cast<float>(plane.positions(v, 0)),
                        static_cast<float>(plane.output_height - plane.positions(v, 1)), 0.0f};
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
    xyz.insert(xyz.end(), p, p + 3);
    normal.insert(normal.end(), {0.0f, 0.0f, 1.0f});
    uv.push_back(static_cast<float>(plane.texture(v, 0) / plane.texture_width));
    uv.push_back(static_cast<float>(plane.texture(v, 1) / plane.texture_height));
  }
  // Flipping y turns positive areas negative: two corners swap, so the triangles face +z.
  std::vector<std::uint32_t> index;
  index.reserve(3 * m);
  for (std::size_t t = 0; t < m; ++t)
    for (int k : {0, 2, 1}) {
      const int id = plane.triangles(t, k);
      if (id < 0 || static_cast<std::size_t>(id) >= n) throw Error("cannot write a textured GLB: vertex id out of range");
      index.push_back(static_cast<std::uint32_t>(id));
    }
  std::string bin;
  const std::size_t off_xyz = append_aligned(bin, xyz.data(), xyz.size() * 4);
  const std::size_t off_normal = append_aligned(bin, normal.data(), normal.size() * 4);
  const std::size_t off_uv = append_aligned(bin, uv.data(), uv.size() * 4);
  const std::size_t off_index = append_aligned(bin, index.data(), index.size() * 4);
  const std::size_t off_png = append_aligned(bin, plane.texture_png.data(), plane.texture_png.size());

  nlohmann::ordered_json gltf;
  gltf["asset"] = {{"version", "2.0"}, {"generator", "volspline lens"}};
  gltf["scene"] = 0;
  gltf["scenes"] = {{{"nodes", {0}}}};
  gltf["nodes"] = {{{"mesh", 0}, {"name", "lens"}}};
  using Json = nlohmann::ordered_json;
  Json primitive = {{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}}, {"indices", 3}, {"material", 0}, {"mode", 4}};
  gltf["meshes"] = Json::array({Json{{"primitives", Json::array({primitive})}}});
  gltf["materials"] = {{{"name", "lens_image"}, {"doubleSided", true},
                        {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}}};
  gltf["textures"] = {{{"sampler", 0}, {"source", 0}}};
  gltf["samplers"] = {{{"magFilter", 9729}, {"minFilter", 9729}, {"wrapS", 33071}, {"wrapT", 33071}}};
  gltf["images"] = {{{"bufferView", 4}, {"mimeType", "image/png"}}};
  gltf["buffers"] = {{{"byteLength", bin.size()}}};
  gltf["bufferViews"] = {{{"buffer", 0}, {"byteOffset", off_xyz}, {"byteLength", xyz.size() * 4}, {"target", 34962}},
                         {{"buffer", 0}, {"byteOffset", off_normal}, {"byteLength", normal.size() * 4}, {"target", 34962}},
                         {{"buffer", 0}, {"byteOffset", off_uv}, {"byteLength", uv.size() * 4}, {"target", 34962}},
                         {{"buffer", 0}, {"byteOffset", off_index}, {"byteLength", index.size() * 4}, {"target", 34963}},
                         {{"buffer", 0}, {"byteOffset", off_png}, {"byteLength", plane.texture_png.size()}}};
  gltf["accessors"] = {
      {{"bufferView", 0}, {"componentType", 5126}, {"count", n}, {"type", "VEC3"}, {"min", {lo[0], lo[1], lo[2]}}, {"max", {hi[0], hi[1], hi[2]}}},
      {{"bufferView", 1}, {"componentType", 5126}, {"count", n}, {"type", "VEC3"}},
      {{"bufferView", 2}, {"componentType", 5126}, {"count", n}, {"type", "VEC2"}},
      {{"bufferView", 3}, {"componentType", 5125}, {"count", index.size()}, {"type", "SCALAR"}}};
  return glb_container(gltf.dump(), std::move(bin));
}

}  // namespace volspline::io
