// SPDX-License-Identifier: MIT
#include "core/io/glb_lines_writer.h"

#include <cassert>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "core/io/file_bytes.h"
#include "core/io/glb_container.h"
#include "core/spline/boundary_tessellation.h"

namespace volspline::io {

namespace {

// Unit vertex normals: the area-weighted mean of the adjacent triangles' normals (so smooth
// shading follows the triangles' outward orientation); a vertex whose triangles all vanish gets
// the mean normal of all triangles, or +z, so that every normal has unit length (glTF §3.7.2.1).
std::vector<float> vertex_normals(const std::vector<float>& xyz, const std::vector<std::uint32_t>& index) {
  const std::size_t n = xyz.size() / 3;
  std::vector<Eigen::Vector3d> sum(n, Eigen::Vector3d::Zero());
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  auto point = [&](std::uint32_t v) { return Eigen::Vector3d(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]); };
  for (std::size_t t = 0; t + 2 < index.size(); t += 3) {
    const Eigen::Vector3d a = point(index[t]), b = point(index[t + 1]), c = point(index[t + 2]);
    const Eigen::Vector3d area = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) sum[index[t + k]] += area;
    total += area;
  }
  const Eigen::Vector3d fallback = total.norm() > 0 ? Eigen::Vector3d(total.normalized()) : Eigen::Vector3d::UnitZ();
  std::vector<float> out;
  out.reserve(xyz.size());
  for (const Eigen::Vector3d& s : sum) {
    const Eigen::Vector3d normal = s.norm() > 1e-300 ? Eigen::Vector3d(s.normalized()) : fallback;
    for (int d = 0; d < 3; ++d) out.push_back(static_cast<float>(normal(d)));
  }
  return out;
}

}  // namespace

std::string serialize_spline_glb(const spline::TSpline& spline, int samples, int lines) {
  assert(spline.dimension() == 3 && samples >= 2 && lines >= 2);
  const spline::BoundaryTessellation boundary = spline::tessellate_boundary(spline, samples, lines);
  const std::vector<float>& surface_xyz = boundary.surface_xyz;
  const std::vector<std::uint32_t>& surface_index = boundary.surface_triangles;
  const std::vector<float>& line_xyz = boundary.line_xyz;
  const std::vector<float> surface_normal = vertex_normals(surface_xyz, surface_index);
  std::string bin;
  const std::size_t off_surface = append_glb_bytes(bin, surface_xyz.data(), surface_xyz.size() * 4);
  const std::size_t off_index = append_glb_bytes(bin, surface_index.data(), surface_index.size() * 4);
  const std::size_t off_lines = append_glb_bytes(bin, line_xyz.data(), line_xyz.size() * 4);
  const std::size_t off_normal = append_glb_bytes(bin, surface_normal.data(), surface_normal.size() * 4);

  nlohmann::ordered_json gltf;
  gltf["asset"] = {{"version", "2.0"}, {"generator", "volspline"}};
  gltf["scene"] = 0;
  gltf["scenes"] = {{{"nodes", {0}}}};
  gltf["nodes"] = {{{"mesh", 0}, {"name", "tspline_boundary"}}};
  gltf["materials"] = {
      {{"name", "surface"}, {"doubleSided", true},
       {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.82, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.8}}}},
      {{"name", "iso_lines"},
       {"pbrMetallicRoughness", {{"baseColorFactor", {0.05, 0.05, 0.1, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}}};
  gltf["meshes"] = {{{"primitives",
                      {{{"attributes", {{"POSITION", 0}, {"NORMAL", 3}}}, {"indices", 1}, {"material", 0}, {"mode", 4}},
                       {{"attributes", {{"POSITION", 2}}}, {"material", 1}, {"mode", 1}}}}}};
  gltf["buffers"] = {{{"byteLength", bin.size()}}};
  gltf["bufferViews"] = {
      {{"buffer", 0}, {"byteOffset", off_surface}, {"byteLength", surface_xyz.size() * 4}, {"target", 34962}},
      {{"buffer", 0}, {"byteOffset", off_index}, {"byteLength", surface_index.size() * 4}, {"target", 34963}},
      {{"buffer", 0}, {"byteOffset", off_lines}, {"byteLength", line_xyz.size() * 4}, {"target", 34962}},
      {{"buffer", 0}, {"byteOffset", off_normal}, {"byteLength", surface_normal.size() * 4}, {"target", 34962}}};
  gltf["accessors"] = {
      {{"bufferView", 0}, {"componentType", 5126}, {"count", surface_xyz.size() / 3}, {"type", "VEC3"},
       {"min", glb_vec3_bound(surface_xyz, false)}, {"max", glb_vec3_bound(surface_xyz, true)}},
      {{"bufferView", 1}, {"componentType", 5125}, {"count", surface_index.size()}, {"type", "SCALAR"}},
      {{"bufferView", 2}, {"componentType", 5126}, {"count", line_xyz.size() / 3}, {"type", "VEC3"},
       {"min", glb_vec3_bound(line_xyz, false)}, {"max", glb_vec3_bound(line_xyz, true)}},
      {{"bufferView", 3}, {"componentType", 5126}, {"count", surface_normal.size() / 3}, {"type", "VEC3"}}};
  return glb_container(gltf.dump(), std::move(bin));
}

void write_spline_glb(const std::string& path, const spline::TSpline& spline, int samples, int lines) {
  write_file_atomic(path, serialize_spline_glb(spline, samples, lines));
}

}  // namespace volspline::io
