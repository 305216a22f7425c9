// SPDX-License-Identifier: MIT
#include "core/io/obj_format.h"

#include <cstdint>
#include <vector>

#include "core/common/error.h"
#include "core/io/mesh_builder.h"
#include "core/io/mesh_text_scanner.h"
#include "core/io/number_text.h"

namespace volspline::io {

mesh::TriangleMesh parse_obj(const std::string& bytes, const std::string& name) {
  if (bytes.empty()) throw Error(name + ": empty file");
  MeshTextScanner scan(bytes, name);
  MeshBuilder builder;
  // Corners are resolved against the final vertex count, so remember where each triangle came from.
  std::vector<std::int64_t> corners;
  std::vector<int> triangle_lines;
  std::vector<std::int64_t> polygon;
  std::string_view token;
  while (scan.next_content_line()) {
    scan.next_token(token);
    if (token == "v") {
      const double x = scan.read_double("x coordinate");
      const double y = scan.read_double("y coordinate");
      const double z = scan.read_double("z coordinate");
      builder.add_vertex(x, y, z);
      if (builder.num_vertices() > kMaxMeshElements) scan.fail("too many vertices");
    } else if (token == "f") {
      polygon.clear();
      while (scan.next_token(token)) {
        const std::string_view index_text = token.substr(0, token.find('/'));
        std::int64_t index = 0;
        if (!parse_int_token(index_text, index))
          scan.fail("bad face corner '" + std::string(token.substr(0, 40)) + "'");
        if (index == 0) scan.fail("face index 0 (OBJ indices start at 1)");
        if (index < 0) {
          // Relative index: -1 is the last vertex defined so far.
          if (index < -builder.num_vertices())
            scan.fail("relative face index " + std::to_string(index) + " out of range (" +
                      std::to_string(builder.num_vertices()) + " vertices so far)");
          index = builder.num_vertices() + index;
        } else {
          index -= 1;
        }
        polygon.push_back(index);
      }
      const std::size_t n = polygon.size();
      if (n < 3) scan.fail("face with " + std::to_string(n) + " corners (needs at least 3)");
      for (std::size_t k = 1; k + 1 < n; ++k) {
        corners.push_back(polygon[0]);
        corners.push_back(polygon[k]);
        corners.push_back(polygon[k + 1]);
        triangle_lines.push_back(scan.line_number());
      }
      if (static_cast<std::int64_t>(triangle_lines.size()) > kMaxMeshElements) scan.fail("too many faces");
    }
  }
  const std::int64_t num_vertices = builder.num_vertices();
  for (std::size_t t = 0; t < triangle_lines.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::int64_t index = corners[3 * t + k];
      if (index >= num_vertices)
        throw Error(name + ":" + std::to_string(triangle_lines[t]) + ": face index " +
                    std::to_string(index + 1) + " out of range (" + std::to_string(num_vertices) +
                    " vertices)");
    }
    builder.add_triangle(static_cast<int>(corners[3 * t]), static_cast<int>(corners[3 * t + 1]),
                         static_cast<int>(corners[3 * t + 2]));
  }
  return builder.finish(name);
}

std::string serialize_obj(const mesh::TriangleMesh& mesh) {
  std::string out;
  out.reserve(static_cast<std::size_t>(mesh.num_vertices()) * 40 + static_cast<std::size_t>(mesh.num_faces()) * 24);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    out += "v";
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, mesh.positions(v, k));
    }
    out += '\n';
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    out += "f";
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, static_cast<long long>(mesh.triangles(f, k)) + 1);
    }
    out += '\n';
  }
  return out;
}

}  // namespace volspline::io
