// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/common/error.h"
#include "core/mesh/triangle_mesh.h"

namespace volspline::io::test {

/// Regular tetrahedron-ish: 4 vertices, 4 outward triangles.
inline mesh::TriangleMesh tetrahedron() {
  mesh::TriangleMesh m;
  m.positions.resize(4, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.triangles.resize(4, 3);
  m.triangles << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return m;
}

/// Axis-aligned cube [offset, offset + size]^3 (vertex v has corner bits x = v&1, y = v>>1&1,
/// z = v>>2&1), 12 outward triangles. The default size 1/3 makes text output keep all 17 digits.
inline mesh::TriangleMesh cube(double offset = 0.1, double size = 1.0 / 3.0) {
  mesh::TriangleMesh m;
  m.positions.resize(8, 3);
  for (int v = 0; v < 8; ++v)
    m.positions.row(v) << offset + (v & 1) * size, offset + ((v >> 1) & 1) * size, offset + ((v >> 2) & 1) * size;
  m.triangles.resize(12, 3);
  m.triangles << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5,
      3, 7, 5;
  return m;
}

/// The message of the volspline::Error that f throws, or "<no error>".
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const volspline::Error& e) {
    return e.what();
  }
  return "<no error>";
}

inline bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace volspline::io::test
