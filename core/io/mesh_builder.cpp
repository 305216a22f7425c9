// SPDX-License-Identifier: MIT
#include "core/io/mesh_builder.h"

#include <algorithm>
#include <cstring>

#include "core/common/error.h"

namespace volspline::io {

void MeshBuilder::add_polygon(const int* ids, std::size_t n) {
  for (std::size_t k = 1; k + 1 < n; ++k) add_triangle(ids[0], ids[k], ids[k + 1]);
}

void MeshBuilder::reserve(std::int64_t vertices, std::int64_t triangles) {
  xyz_.reserve(xyz_.size() + static_cast<std::size_t>(std::clamp<std::int64_t>(vertices, 0, kMaxMeshElements)) * 3);
  ids_.reserve(ids_.size() + static_cast<std::size_t>(std::clamp<std::int64_t>(triangles, 0, kMaxMeshElements)) * 3);
}

mesh::TriangleMesh MeshBuilder::finish(const std::string& name) {
  if (num_vertices() == 0) throw Error(name + ": no vertices");
  if (num_triangles() == 0) throw Error(name + ": no faces");
  if (num_vertices() > kMaxMeshElements)
    throw Error(name + ": too many vertices (" + std::to_string(num_vertices()) + ")");
  if (num_triangles() > kMaxMeshElements)
    throw Error(name + ": too many faces (" + std::to_string(num_triangles()) + ")");
  mesh::TriangleMesh mesh;
  mesh.positions.resize(num_vertices(), 3);
  mesh.triangles.resize(num_triangles(), 3);
  std::memcpy(mesh.positions.data(), xyz_.data(), xyz_.size() * sizeof(double));
  std::memcpy(mesh.triangles.data(), ids_.data(), ids_.size() * sizeof(int));
  xyz_.clear();
  ids_.clear();
  return mesh;
}

}  // namespace volspline::io
