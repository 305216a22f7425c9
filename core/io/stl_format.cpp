// SPDX-License-Identifier: MIT
#include "core/io/stl_format.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>

#include "core/common/error.h"
#include "core/io/mesh_builder.h"
#include "core/io/mesh_text_scanner.h"

namespace volspline::io {

namespace {

// Gives each distinct position an id in order of first appearance (exact comparison; -0 == +0).
class VertexMerger {
 public:
  int id(double x, double y, double z, MeshBuilder& builder) {
    const auto [it, inserted] = ids_.emplace(std::array<double, 3>{x, y, z}, static_cast<int>(ids_.size()));
    if (inserted) builder.add_vertex(x, y, z);
    return it->second;
  }

 private:
  std::map<std::array<double, 3>, int> ids_;
};

constexpr std::size_t kBinaryHeader = 84;
constexpr std::size_t kBinaryTriangle = 50;

mesh::TriangleMesh parse_binary(const std::string& bytes, const std::string& name, std::uint32_t num_triangles) {
  MeshBuilder builder;
  builder.reserve(0, num_triangles);
  VertexMerger merger;
  const char* data = bytes.data() + kBinaryHeader;
  for (std::uint32_t t = 0; t < num_triangles; ++t, data += kBinaryTriangle) {
    int ids[3];
    for (int corner = 0; corner < 3; ++corner) {
      float xyz[3];
      // Little-endian host assumed (x86-64, wasm32); STL is little-endian. Skip the normal.
      std::memcpy(xyz, data + 12 + 12 * corner, 12);
      for (int k = 0; k < 3; ++k) {
        if (std::isnan(xyz[k]))
          throw Error(name + ": triangle " + std::to_string(t) + ": NaN coordinate");
        if (std::isinf(xyz[k]))
          throw Error(name + ": triangle " + std::to_string(t) + ": infinite coordinate");
      }
      ids[corner] = merger.id(xyz[0], xyz[1], xyz[2], builder);
    }
    builder.add_triangle(ids[0], ids[1], ids[2]);
  }
  return builder.finish(name);
}

mesh::TriangleMesh parse_ascii(const std::string& bytes, const std::string& name) {
  MeshTextScanner scan(bytes, name);
  MeshBuilder builder;
  VertexMerger merger;
  std::string_view token;
  if (!scan.next_token_any_line(token) || token != "solid") scan.fail("not an STL file");
  scan.next_line();  // the rest of the solid line is its name
  bool in_facet = false;
  bool ended = false;
  int corners[3];
  int num_corners = 0;
  while (scan.next_token_any_line(token)) {
    if (token == "facet") {
      if (in_facet) scan.fail("'facet' inside a facet");
      in_facet = true;
      num_corners = 0;
      scan.next_line();  // normal is ignored
    } else if (token == "vertex") {
      if (!in_facet) scan.fail("'vertex' outside a facet");
      if (num_corners == 3) scan.fail("facet with more than 3 vertices");
      const double x = scan.read_double("x coordinate");
      const double y = scan.read_double("y coordinate");
      const double z = scan.read_double("z coordinate");
      corners[num_corners++] = merger.id(x, y, z, builder);
    } else if (token == "endfacet") {
      if (!in_facet) scan.fail("'endfacet' outside a facet");
      if (num_corners != 3) scan.fail("facet with " + std::to_string(num_corners) + " vertices (needs 3)");
      builder.add_triangle(corners[0], corners[1], corners[2]);
      if (builder.num_triangles() > kMaxMeshElements) scan.fail("too many facets");
      in_facet = false;
    } else if (token == "outer" || token == "loop" || token == "endloop") {
      continue;
    } else if (token == "endsolid") {
      if (in_facet) scan.fail("'endsolid' inside a facet");
      ended = true;
      scan.next_line();
    } else if (token == "solid") {
      if (in_facet) scan.fail("'solid' inside a facet");
      ended = false;
      scan.next_line();
    } else {
      scan.fail("unexpected '" + std::string(token.substr(0, 30)) + "'");
    }
  }
  if (in_facet) throw Error(name + ": truncated: file ends inside facet " + std::to_string(builder.num_triangles()));
  if (!ended && builder.num_triangles() > 0) throw Error(name + ": truncated: no 'endsolid'");
  return builder.finish(name);
}

// ASCII STL: starts with "solid" and has no NUL byte near the start (binary headers often begin
// with "solid" too, but their triangle data holds zero bytes).
bool looks_ascii(const std::string& bytes) {
  if (bytes.find('\0') < 512) return false;
  std::size_t pos = 0;
  while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos]))) ++pos;
  return bytes.compare(pos, 5, "solid") == 0;
}

}  // namespace

mesh::TriangleMesh parse_stl(const std::string& bytes, const std::string& name) {
  if (bytes.empty()) throw Error(name + ": empty file");
  std::uint32_t num_triangles = 0;
  if (bytes.size() >= kBinaryHeader) std::memcpy(&num_triangles, bytes.data() + 80, 4);
  if (bytes.size() >= kBinaryHeader &&
      bytes.size() - kBinaryHeader == static_cast<std::uint64_t>(num_triangles) * kBinaryTriangle) {
    if (num_triangles == 0) throw Error(name + ": no faces (binary STL with 0 triangles)");
    return parse_binary(bytes, name, num_triangles);
  }
  if (looks_ascii(bytes)) return parse_ascii(bytes, name);
  if (bytes.size() < kBinaryHeader)
    throw Error(name + ": truncated binary STL (" + std::to_string(bytes.size()) + " bytes, header needs 84)");
  throw Error(name + ": binary STL size mismatch: header says " + std::to_string(num_triangles) +
              " triangles (" + std::to_string(kBinaryHeader + static_cast<std::uint64_t>(num_triangles) * kBinaryTriangle) +
              " bytes) but the file has " + std::to_string(bytes.size()) + " bytes");
}

}  // namespace volspline::io
