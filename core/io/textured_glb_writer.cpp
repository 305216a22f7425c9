// SPDX-License-Identifier: MIT
#include "core/io/textured_glb_writer.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "core/io/glb_container.h"

namespace volspline::io {

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
  const std::size_t off_xyz = append_glb_bytes(bin, xyz.data(), xyz.size() * 4);
  const std::size_t off_normal = append_glb_bytes(bin, normal.data(), normal.size() * 4);
  const std::size_t off_uv = append_glb_bytes(bin, uv.data(), uv.size() * 4);
  const std::size_t off_index = append_glb_bytes(bin, index.data(), index.size() * 4);
  const std::size_t off_png = append_glb_bytes(bin, plane.texture_png.data(), plane.texture_png.size());

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
