// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::io {

/// Largest vertex or face count a reader accepts: ids are int and a coordinate array of this
/// many rows still fits in memory comfortably.
constexpr std::int64_t kMaxMeshElements = 200'000'000;

/// Collects vertices and triangles while a reader parses, then hands out a TriangleMesh.
/// Readers check indices themselves (they know the line or element); the builder checks the
/// whole-mesh conditions.
class MeshBuilder {
 public:
  /// Appends a vertex (model units); the caller has checked that it is finite.
  void add_vertex(double x, double y, double z) {
    xyz_.push_back(x);
    xyz_.push_back(y);
    xyz_.push_back(z);
  }
  /// Appends a triangle of 0-based vertex ids (checked by the caller).
  void add_triangle(int a, int b, int c) {
    ids_.push_back(a);
    ids_.push_back(b);
    ids_.push_back(c);
  }
  /// Fan-triangulates a polygon of n >= 3 vertex ids: (0,1,2), (0,2,3), ...
  void add_polygon(const int* ids, std::size_t n);

  std::int64_t num_vertices() const { return static_cast<std::int64_t>(xyz_.size() / 3); }
  std::int64_t num_triangles() const { return static_cast<std::int64_t>(ids_.size() / 3); }
  /// Reserves room for `vertices` and `triangles` more (callers bound these by the input size).
  void reserve(std::int64_t vertices, std::int64_t triangles);

  /// Builds the mesh. Throws volspline::Error "name: no vertices" / "name: no faces" when empty
  /// or when the counts exceed kMaxMeshElements.
  mesh::TriangleMesh finish(const std::string& name);

 private:
  std::vector<double> xyz_;
  std::vector<int> ids_;
};

}  // namespace volspline::io
