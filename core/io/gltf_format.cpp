// SPDX-License-Identifier: MIT
#include "core/io/gltf_format.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>  // tinygltf needs it
#include <limits>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "core/io/file_bytes.h"
#include "core/io/json_depth.h"
#include "core/io/mesh_builder.h"

// Debian's tiny_gltf.h includes <nlohmann/json.hpp> and <stb_image.h>. Images are never decoded
// here, so stb stays out (image_io owns stb's implementation) and files are only read through
// the callbacks below. This is the one translation unit that compiles tinygltf.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_FS
#include <tiny_gltf.h>

namespace volspline::io {

namespace {

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                void*) {
  return true;
}

bool file_exists(const std::string& path, void* base_dir) {
  if (base_dir == nullptr) return false;
  return is_regular_file(path);
}

std::string expand_path(const std::string& path, void*) { return path; }

// External buffers are read like every input: regular files only (a device or FIFO named by a
// buffer's uri is refused, not read until memory runs out).
bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* base_dir) {
  if (base_dir == nullptr) {
    if (err) *err += "external file '" + path + "' not allowed when parsing from memory\n";
    return false;
  }
  try {
    const std::string bytes = read_file_bytes(path);
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const Error& e) {
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
}

bool write_whole_file(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not supported\n";
  return false;
}

// Strided, bounds-checked read access to an accessor's elements.
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, int accessor_id, int want_type, const std::string& where) {
    if (accessor_id < 0 || accessor_id >= static_cast<int>(model.accessors.size()))
      throw Error(where + ": accessor " + std::to_string(accessor_id) + " does not exist");
    const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(accessor_id)];
    const std::string what = where + ": accessor " + std::to_string(accessor_id);
    if (accessor.sparse.isSparse) throw Error(what + " is sparse (not supported)");
    if (accessor.type != want_type)
      throw Error(what + " has type " + std::to_string(accessor.type) + ", expected " + std::to_string(want_type));
    num_components_ = want_type == TINYGLTF_TYPE_VEC3 ? 3 : 1;
    component_type_ = accessor.componentType;
    normalized_ = accessor.normalized;
    const int component_size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(component_type_));
    if (component_size <= 0) throw Error(what + " has an unknown component type");
    component_size_ = static_cast<std::size_t>(component_size);
    count_ = accessor.count;
    if (accessor.bufferView < 0 || accessor.bufferView >= static_cast<int>(model.bufferViews.size()))
      throw Error(what + " has no valid bufferView");
    const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(accessor.bufferView)];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size()))
      throw Error(what + ": bufferView " + std::to_string(accessor.bufferView) + " has no valid buffer");
    const std::vector<unsigned char>& data = model.buffers[static_cast<std::size_t>(view.buffer)].data;
    const std::size_t element_size = component_size_ * static_cast<std::size_t>(num_components_);
    stride_ = view.byteStride == 0 ? element_size : view.byteStride;
    if (stride_ < element_size) throw Error(what + ": byteStride smaller than an element");
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
      throw Error(what + ": bufferView " + std::to_string(accessor.bufferView) + " lies outside its buffer");
    if (count_ == 0) return;
    if (accessor.byteOffset > view.byteLength || view.byteLength - accessor.byteOffset < element_size ||
        (count_ - 1) > (view.byteLength - accessor.byteOffset - element_size) / stride_)
      throw Error(what + ": " + std::to_string(count_) + " elements do not fit in bufferView " +
                  std::to_string(accessor.bufferView));
    base_ = data.data() + view.byteOffset + accessor.byteOffset;
  }

  std::size_t count() const { return count_; }
  bool is_integer() const {
    return component_type_ != TINYGLTF_COMPONENT_TYPE_FLOAT && component_type_ != TINYGLTF_COMPONENT_TYPE_DOUBLE;
  }

  double value(std::size_t element, int component) const {
    const unsigned char* p = base_ + element * stride_ + static_cast<std::size_t>(component) * component_size_;
    switch (component_type_) {
      case TINYGLTF_COMPONENT_TYPE_BYTE: return normalize(load<std::int8_t>(p), 127.0);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalize(load<std::uint8_t>(p), 255.0);
      case TINYGLTF_COMPONENT_TYPE_SHORT: return normalize(load<std::int16_t>(p), 32767.0);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return normalize(load<std::uint16_t>(p), 65535.0);
      case TINYGLTF_COMPONENT_TYPE_INT: return static_cast<double>(load<std::int32_t>(p));
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return static_cast<double>(load<std::uint32_t>(p));
      case TINYGLTF_COMPONENT_TYPE_FLOAT: return static_cast<double>(load<float>(p));
      case TINYGLTF_COMPONENT_TYPE_DOUBLE: return load<double>(p);
      default: return 0.0;
    }
  }

 private:
  template <typename T>
  static T load(const unsigned char* p) {
    T value;
    std::memcpy(&value, p, sizeof(T));  // glTF is little-endian, like the hosts we build for
    return value;
  }
  double normalize(double raw, double scale) const { return normalized_ ? std::max(raw / scale, -1.0) : raw; }

  const unsigned char* base_ = nullptr;
  std::size_t count_ = 0;
  std::size_t stride_ = 0;
  std::size_t component_size_ = 0;
  int component_type_ = 0;
  int num_components_ = 0;
  bool normalized_ = false;
};

Eigen::Matrix4d local_transform(const tinygltf::Node& node, const std::string& where) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) throw Error(where + ": matrix must have 16 numbers");
    for (int k = 0; k < 16; ++k) m(k % 4, k / 4) = node.matrix[static_cast<std::size_t>(k)];  // column-major
    return m;
  }
  Eigen::Matrix3d linear = Eigen::Matrix3d::Identity();
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4) throw Error(where + ": rotation must have 4 numbers");
    Eigen::Quaterniond q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    if (!(q.norm() > 0)) throw Error(where + ": zero rotation quaternion");
    linear = q.normalized().toRotationMatrix();
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3) throw Error(where + ": scale must have 3 numbers");
    linear = linear * Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]).asDiagonal();
  }
  m.topLeftCorner<3, 3>() = linear;
  if (!node.translation.empty()) {
    if (node.translation.size() != 3) throw Error(where + ": translation must have 3 numbers");
    m.topRightCorner<3, 1>() = Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]);
  }
  return m;
}

void append_mesh(const tinygltf::Model& model, int mesh_id, const Eigen::Matrix4d& world, const std::string& name,
                 MeshBuilder& builder) {
  if (mesh_id < 0 || mesh_id >= static_cast<int>(model.meshes.size()))
    throw Error(name + ": mesh " + std::to_string(mesh_id) + " does not exist");
  const tinygltf::Mesh& mesh = model.meshes[static_cast<std::size_t>(mesh_id)];
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const tinygltf::Primitive& primitive = mesh.primitives[p];
    if (primitive.mode != TINYGLTF_MODE_TRIANGLES && primitive.mode != -1) continue;
    const std::string where = name + ": mesh " + std::to_string(mesh_id) + " primitive " + std::to_string(p);
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) throw Error(where + ": no POSITION attribute");
    const AccessorReader positions(model, position->second, TINYGLTF_TYPE_VEC3, where);
    const std::size_t num_vertices = positions.count();
    const std::int64_t first = builder.num_vertices();
    if (static_cast<std::int64_t>(num_vertices) > kMaxMeshElements - first)
      throw Error(where + ": too many vertices in total");
    // Non-indexed primitives (three.js, flat-shaded Blender exports) repeat every shared corner:
    // exactly coincident positions are welded into one vertex, as STL's are.
    const bool weld = primitive.indices < 0;
    std::map<std::array<double, 3>, int> welded;
    std::vector<int> vertex_id(num_vertices);
    for (std::size_t v = 0; v < num_vertices; ++v) {
      const Eigen::Vector4d local(positions.value(v, 0), positions.value(v, 1), positions.value(v, 2), 1.0);
      const Eigen::Vector3d xyz = (world * local).head<3>();
      if (!xyz.allFinite())
        throw Error(where + ": vertex " + std::to_string(v) + " has a NaN or infinite coordinate");
      const int next = static_cast<int>(builder.num_vertices());
      if (weld) {
        const auto [it, inserted] = welded.emplace(std::array<double, 3>{xyz.x(), xyz.y(), xyz.z()}, next);
        vertex_id[v] = it->second;
        if (!inserted) continue;
      } else {
        vertex_id[v] = next;
      }
      builder.add_vertex(xyz.x(), xyz.y(), xyz.z());
    }
    // A mirroring transform turns triangles inside out; swap two corners to keep them outward.
    const bool flip = world.topLeftCorner<3, 3>().determinant() < 0;
    auto add = [&](std::size_t a, std::size_t b, std::size_t c) {
      const int ia = vertex_id[a];
      const int ib = vertex_id[b];
      const int ic = vertex_id[c];
      if (flip)
        builder.add_triangle(ia, ic, ib);
      else
        builder.add_triangle(ia, ib, ic);
    };
    if (primitive.indices < 0) {
      if (num_vertices % 3 != 0)
        throw Error(where + ": " + std::to_string(num_vertices) + " unindexed vertices are not a multiple of 3");
      for (std::size_t t = 0; t < num_vertices / 3; ++t) add(3 * t, 3 * t + 1, 3 * t + 2);
      continue;
    }
    const AccessorReader indices(model, primitive.indices, TINYGLTF_TYPE_SCALAR, where + " indices");
    if (!indices.is_integer()) throw Error(where + ": indices must have an integer component type");
    if (indices.count() % 3 != 0)
      throw Error(where + ": index count " + std::to_string(indices.count()) + " is not a multiple of 3");
    if (static_cast<std::int64_t>(indices.count() / 3) > kMaxMeshElements - builder.num_triangles())
      throw Error(where + ": too many triangles in total");
    std::size_t corner[3];
    for (std::size_t i = 0; i < indices.count(); ++i) {
      const double index = indices.value(i, 0);
      if (index < 0 || index >= static_cast<double>(num_vertices))
        throw Error(where + ": index " + std::to_string(static_cast<long long>(index)) + " out of range (" +
                    std::to_string(num_vertices) + " vertices)");
      corner[i % 3] = static_cast<std::size_t>(index);
      if (i % 3 == 2) add(corner[0], corner[1], corner[2]);
    }
  }
}

// Draco and meshopt store the geometry in a compressed form that this reader does not decode;
// without this check tinygltf fails later with "invalid bufferView" or "Invalid byteLength".
void refuse_compressed_meshes(const std::string& bytes, const std::string& name) {
  std::string json_text;
  if (bytes.size() >= 20 && bytes.compare(0, 4, "glTF") == 0) {
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    if (length > bytes.size() - 20) return;  // tinygltf names the broken chunk
    json_text = bytes.substr(20, length);
  } else {
    json_text = bytes;
  }
  const auto json = nlohmann::json::parse(json_text, nullptr, false);
  if (json.is_discarded() || !json.is_object()) return;
  for (const char* list : {"extensionsRequired", "extensionsUsed"}) {
    const auto it = json.find(list);
    if (it == json.end() || !it->is_array()) continue;
    for (const auto& extension : *it) {
      if (!extension.is_string()) continue;
      const std::string id = extension.get<std::string>();
      if (id == "KHR_draco_mesh_compression" || id == "EXT_meshopt_compression" || id == "KHR_meshopt_compression")
        throw Error(name + ": meshes compressed with " + id +
                    " are not supported; write the file without mesh compression (e.g. gltf-pipeline without -d, "
                    "gltfpack without -cc)");
    }
  }
}

}  // namespace

mesh::TriangleMesh parse_gltf(const std::string& bytes, const std::string& name,
                              const std::optional<std::string>& base_dir) {
  if (bytes.empty()) throw Error(name + ": empty file");
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) throw Error(name + ": file larger than 4 GB");
  // tinygltf's JSON parse recurses per nesting level: measure the depth first (GLB: its JSON chunk).
  if (bytes.size() >= 20 && bytes.compare(0, 4, "glTF") == 0) {
    std::uint32_t chunk_length = 0;
    std::memcpy(&chunk_length, bytes.data() + 12, 4);
    check_json_depth(bytes.data() + 20, std::min<std::size_t>(chunk_length, bytes.size() - 20), name);
  } else {
    check_json_depth(bytes.data(), bytes.size(), name);
  }
  refuse_compressed_meshes(bytes, name);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  std::string dir = base_dir.value_or("");
  loader.SetFsCallbacks(tinygltf::FsCallbacks{file_exists, expand_path, read_whole_file, write_whole_file,
                                              base_dir ? static_cast<void*>(&dir) : nullptr});
  tinygltf::Model model;
  std::string err, warn;
  bool ok = false;
  try {
    if (bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0)
      ok = loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                       static_cast<unsigned int>(bytes.size()), dir);
    else
      ok = loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), static_cast<unsigned int>(bytes.size()),
                                      dir);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(name + ": invalid glTF: " + e.what());
  }
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    for (char& c : err)
      if (c == '\n') c = ' ';
    throw Error(name + ": invalid glTF: " + (err.empty() ? std::string("unknown error") : err.substr(0, 300)));
  }

  MeshBuilder builder;
  std::vector<std::pair<int, Eigen::Matrix4d>> stack;
  if (!model.scenes.empty()) {
    const int scene_id = model.defaultScene >= 0 && model.defaultScene < static_cast<int>(model.scenes.size())
                             ? model.defaultScene
                             : 0;
    const auto& roots = model.scenes[static_cast<std::size_t>(scene_id)].nodes;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, Eigen::Matrix4d::Identity());
  } else if (!model.nodes.empty()) {
    std::vector<char> is_child(model.nodes.size(), 0);
    for (const auto& node : model.nodes)
      for (int child : node.children)
        if (child >= 0 && child < static_cast<int>(model.nodes.size())) is_child[static_cast<std::size_t>(child)] = 1;
    for (int n = static_cast<int>(model.nodes.size()) - 1; n >= 0; --n)
      if (!is_child[static_cast<std::size_t>(n)]) stack.emplace_back(n, Eigen::Matrix4d::Identity());
  } else {
    for (int m = 0; m < static_cast<int>(model.meshes.size()); ++m)
      append_mesh(model, m, Eigen::Matrix4d::Identity(), name, builder);
  }
  // Depth-first in document order; a node reached twice means a cycle or shared child (invalid).
  std::vector<char> visited(model.nodes.size(), 0);
  while (!stack.empty()) {
    const auto [node_id, parent] = stack.back();
    stack.pop_back();
    if (node_id < 0 || node_id >= static_cast<int>(model.nodes.size()))
      throw Error(name + ": node " + std::to_string(node_id) + " does not exist");
    if (visited[static_cast<std::size_t>(node_id)])
      throw Error(name + ": node " + std::to_string(node_id) + " is reached twice (cycle or shared child)");
    visited[static_cast<std::size_t>(node_id)] = 1;
    const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(node_id)];
    const Eigen::Matrix4d world = parent * local_transform(node, name + ": node " + std::to_string(node_id));
    if (node.mesh >= 0) append_mesh(model, node.mesh, world, name, builder);
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.emplace_back(*it, world);
  }
  if (builder.num_triangles() == 0) throw Error(name + ": no faces (no TRIANGLES primitive with triangles)");
  return builder.finish(name);
}

std::string serialize_glb(const mesh::TriangleMesh& mesh) {
  const int n = mesh.num_vertices();
  const int m = mesh.num_faces();
  std::string bin(static_cast<std::size_t>(n) * 12 + static_cast<std::size_t>(m) * 12, '\0');
  std::vector<float> lo(3, std::numeric_limits<float>::max()), hi(3, std::numeric_limits<float>::lowest());
  char* out = bin.data();
  for (int v = 0; v < n; ++v) {
    for (int k = 0; k < 3; ++k) {
      const double value = mesh.positions(v, k);
      if (!(std::abs(value) <= static_cast<double>(std::numeric_limits<float>::max())))
        throw Error("cannot write GLB: vertex " + std::to_string(v) + " coordinate is outside float range");
      const float f = static_cast<float>(value);
      lo[static_cast<std::size_t>(k)] = std::min(lo[static_cast<std::size_t>(k)], f);
      hi[static_cast<std::size_t>(k)] = std::max(hi[static_cast<std::size_t>(k)], f);
      std::memcpy(out, &f, 4);
      out += 4;
    }
  }
  for (int f = 0; f < m; ++f) {
    for (int k = 0; k < 3; ++k) {
      const auto id = static_cast<std::uint32_t>(mesh.triangles(f, k));
      std::memcpy(out, &id, 4);
      out += 4;
    }
  }
  if (n == 0) lo = hi = std::vector<float>(3, 0.0f);

  using Json = nlohmann::ordered_json;
  Json j;
  j["asset"] = {{"version", "2.0"}, {"generator", "volspline"}};
  j["scene"] = 0;
  j["scenes"] = Json::array({{{"nodes", {0}}}});
  j["nodes"] = Json::array({{{"mesh", 0}}});
  j["meshes"] = Json::array({{{"primitives", Json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"mode", 4}}})}}});
  Json position = {{"bufferView", 0}, {"componentType", TINYGLTF_COMPONENT_TYPE_FLOAT}, {"count", n}, {"type", "VEC3"}};
  position["min"] = {lo[0], lo[1], lo[2]};
  position["max"] = {hi[0], hi[1], hi[2]};
  const Json indices = {{"bufferView", 1}, {"componentType", TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT}, {"count", 3LL * m},
                        {"type", "SCALAR"}};
  j["accessors"] = Json::array({position, indices});
  j["bufferViews"] = Json::array(
      {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 12LL * n}, {"target", TINYGLTF_TARGET_ARRAY_BUFFER}},
       {{"buffer", 0}, {"byteOffset", 12LL * n}, {"byteLength", 12LL * m}, {"target", TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER}}});
  j["buffers"] = Json::array({{{"byteLength", bin.size()}}});
  std::string json = j.dump();
  while (json.size() % 4 != 0) json += ' ';  // chunks are 4-byte aligned; JSON pads with spaces

  std::string glb;
  auto put32 = [&glb](std::uint32_t value) {
    char raw[4];
    std::memcpy(raw, &value, 4);
    glb.append(raw, 4);
  };
  const bool has_bin = !bin.empty();
  glb.reserve(12 + 8 + json.size() + (has_bin ? 8 + bin.size() : 0));
  glb += "glTF";
  put32(2);
  put32(static_cast<std::uint32_t>(12 + 8 + json.size() + (has_bin ? 8 + bin.size() : 0)));
  put32(static_cast<std::uint32_t>(json.size()));
  put32(0x4E4F534Au);  // "JSON"
  glb += json;
  if (has_bin) {
    put32(static_cast<std::uint32_t>(bin.size()));
    put32(0x004E4942u);  // "BIN\0"
    glb += bin;
  }
  return glb;
}

}  // namespace volspline::io
