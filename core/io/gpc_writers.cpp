// SPDX-License-Identifier: MIT
#include "core/io/gpc_writers.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include <nlohmann/json.hpp>

#include "core/io/file_bytes.h"
#include "core/io/glb_container.h"
#include "core/io/vtk_xml_writer.h"
#include "core/mesh/hex_quality.h"

namespace volspline::io {

std::string serialize_hex_mesh_vtu(const HexMeshView& mesh) {
  const mesh::Positions& p = *mesh.xyz;
  std::vector<double> xyz, quality, cuboid, padding;
  std::vector<std::int64_t> connectivity, offsets;
  xyz.reserve(3 * p.rows());
  for (int r = 0; r < p.rows(); ++r)
    for (int d = 0; d < 3; ++d) xyz.push_back(p(r, d));
  // VTK_HEXAHEDRON corner order: bottom face counter-clockwise, then top face.
  const int order[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  for (std::size_t h = 0; h < mesh.hexes->size(); ++h) {
    const std::array<int, 8>& hex = (*mesh.hexes)[h];
    std::array<Eigen::Vector3d, 8> x;
    for (int c = 0; c < 8; ++c) x[c] = p.row(hex[c]).transpose();
    for (int c = 0; c < 8; ++c) connectivity.push_back(hex[order[c]]);
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    quality.push_back(mesh.scaled_jacobian ? (*mesh.scaled_jacobian)[h] : mesh::hex_scaled_jacobian(x));
    cuboid.push_back(static_cast<double>((*mesh.cuboid)[h]));
    if (mesh.padding) padding.push_back((*mesh.padding)[h] ? 1.0 : 0.0);
  }
  const std::vector<std::uint8_t> types(offsets.size(), 12);  // VTK_HEXAHEDRON
  VtkXmlWriter writer;
  std::string body = "<Piece NumberOfPoints=\"" + std::to_string(p.rows()) + "\" NumberOfCells=\"" +
                     std::to_string(offsets.size()) + "\">\n";
  body += "<CellData Scalars=\"scaled_jacobian\">\n" + writer.add("scaled_jacobian", quality) +
          writer.add("cuboid", cuboid) + (mesh.padding ? writer.add("padding", padding) : std::string()) +
          "</CellData>\n";
  body += "<Points>\n" + writer.add("Points", xyz, 3) + "</Points>\n<Cells>\n";
  body += writer.add("connectivity", connectivity) + writer.add("offsets", offsets) + writer.add("types", types);
  body += "</Cells>\n</Piece>\n";
  return writer.document("UnstructuredGrid", "", body);
}

std::array<float, 3> segment_colour(int s) {
  const double h = std::fmod(s * 0.61803398875, 1.0) * 6.0;
  const double f = h - std::floor(h);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h) % 6) {
    case 0: r = 1; g = f; break;
    case 1: r = 1 - f; g = 1; break;
    case 2: g = 1; b = f; break;
    case 3: g = 1 - f; b = 1; break;
    case 4: r = f; b = 1; break;
    default: r = 1; b = 1 - f; break;
  }
  return {static_cast<float>(0.25 + 0.7 * r), static_cast<float>(0.25 + 0.7 * g), static_cast<float>(0.25 + 0.7 * b)};
}

std::string serialize_segmented_glb(const mesh::TriangleMesh& surface, const std::vector<int>& face_segment,
                                    const std::vector<std::vector<Eigen::Vector3d>>& polylines,
                                    const std::vector<Eigen::Vector3d>& points) {
  std::vector<float> xyz, normal, colour, line_xyz, point_xyz;
  for (int t = 0; t < surface.num_faces(); ++t) {
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = surface.positions.row(surface.triangles(t, k)).transpose();
    Eigen::Vector3d nrm = (p[1] - p[0]).cross(p[2] - p[0]);
    nrm = nrm.norm() > 0.0 ? Eigen::Vector3d(nrm.normalized()) : Eigen::Vector3d::UnitZ();
    const auto c = segment_colour(std::max(face_segment[t], 0));
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) {
        xyz.push_back(static_cast<float>(p[k](d)));
        normal.push_back(static_cast<float>(nrm(d)));
        colour.push_back(c[d]);
      }
  }
  for (const auto& line : polylines)
    for (std::size_t i = 0; i + 1 < line.size(); ++i)
      for (int e = 0; e < 2; ++e)
        for (int d = 0; d < 3; ++d) line_xyz.push_back(static_cast<float>(line[i + e](d)));
  for (const Eigen::Vector3d& p : points)
    for (int d = 0; d < 3; ++d) point_xyz.push_back(static_cast<float>(p(d)));

  using Json = nlohmann::ordered_json;
  std::string bin;
  Json views = Json::array(), accessors = Json::array(), primitives = Json::array();
  auto add = [&](const std::vector<float>& data, bool with_bounds) {
    const std::size_t offset = append_glb_bytes(bin, data.data(), data.size() * 4);
    views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", data.size() * 4}, {"target", 34962}});
    Json a = {{"bufferView", views.size() - 1}, {"componentType", 5126}, {"count", data.size() / 3}, {"type", "VEC3"}};
    if (with_bounds) {
      a["min"] = glb_vec3_bound(data, false);
      a["max"] = glb_vec3_bound(data, true);
    }
    accessors.push_back(a);
    return static_cast<int>(accessors.size()) - 1;
  };
  Json materials = Json::array();
  if (!xyz.empty()) {
    const int pos = add(xyz, true), nrm = add(normal, false), col = add(colour, false);
    materials.push_back({{"name", "cuboids"}, {"doubleSided", true},
                         {"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.8}}}});
    primitives.push_back({{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"COLOR_0", col}}},
                          {"material", materials.size() - 1}, {"mode", 4}});
  }
  if (!line_xyz.empty()) {
    const int pos = add(line_xyz, true);
    materials.push_back({{"name", "poly_edges"},
                         {"pbrMetallicRoughness", {{"baseColorFactor", {0.05, 0.05, 0.1, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}});
    primitives.push_back({{"attributes", {{"POSITION", pos}}}, {"material", materials.size() - 1}, {"mode", 1}});
  }
  if (!point_xyz.empty()) {
    const int pos = add(point_xyz, true);
    materials.push_back({{"name", "corners"},
                         {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.1, 0.1, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}});
    primitives.push_back({{"attributes", {{"POSITION", pos}}}, {"material", materials.size() - 1}, {"mode", 0}});
  }
  Json gltf;
  gltf["asset"] = {{"version", "2.0"}, {"generator", "volspline"}};
  gltf["scene"] = 0;
  gltf["scenes"] = {{{"nodes", {0}}}};
  gltf["nodes"] = {{{"mesh", 0}, {"name", "gpc_segmentation"}}};
  gltf["materials"] = materials;
  gltf["meshes"] = {{{"primitives", primitives}}};
  gltf["buffers"] = {{{"byteLength", bin.size()}}};
  gltf["bufferViews"] = views;
  gltf["accessors"] = accessors;
  return glb_container(gltf.dump(), std::move(bin));
}

void write_segmented_glb(const std::string& path, const mesh::TriangleMesh& surface,
                         const std::vector<int>& face_segment,
                         const std::vector<std::vector<Eigen::Vector3d>>& polylines,
                         const std::vector<Eigen::Vector3d>& points) {
  write_file_atomic(path, serialize_segmented_glb(surface, face_segment, polylines, points));
}

}  // namespace volspline::io
