// SPDX-License-Identifier: MIT
#include "core/io/off_format.h"

#include <cstdint>
#include <vector>

#include "core/common/error.h"
#include "core/io/mesh_builder.h"
#include "core/io/mesh_text_scanner.h"
#include "core/io/number_text.h"

namespace volspline::io {

namespace {

// [ST][C][N]OFF; the 4D (4OFF) and dimension-prefixed (nOFF) variants are not meshes we read.
bool is_off_keyword(std::string_view word) {
  if (word.size() < 3 || word.substr(word.size() - 3) != "OFF") return false;
  std::string_view prefix = word.substr(0, word.size() - 3);
  if (prefix.substr(0, 2) == "ST") prefix.remove_prefix(2);
  if (!prefix.empty() && prefix[0] == 'C') prefix.remove_prefix(1);
  if (!prefix.empty() && prefix[0] == 'N') prefix.remove_prefix(1);
  return prefix.empty();
}

}  // namespace

mesh::TriangleMesh parse_off(const std::string& bytes, const std::string& name) {
  if (bytes.empty()) throw Error(name + ": empty file");
  MeshTextScanner scan(bytes, name);
  if (!scan.next_content_line()) throw Error(name + ": empty file (no OFF header)");
  std::string_view token;
  scan.next_token(token);
  if (!is_off_keyword(token)) scan.fail("not an OFF file (header '" + std::string(token.substr(0, 20)) + "')");
  if (scan.line_done() && !scan.next_content_line()) scan.fail("missing vertex/face counts after OFF header");
  const std::int64_t num_vertices = scan.read_int("vertex count");
  const std::int64_t num_faces = scan.read_int("face count");
  if (num_vertices < 0) scan.fail("negative vertex count " + std::to_string(num_vertices));
  if (num_faces < 0) scan.fail("negative face count " + std::to_string(num_faces));
  // Each vertex or face needs at least one line of a few bytes: larger counts cannot be real.
  const auto bound = static_cast<std::int64_t>(scan.bytes_left() / 2 + 1);
  if (num_vertices > bound || num_vertices > kMaxMeshElements)
    scan.fail("vertex count " + std::to_string(num_vertices) + " too large for a file of " +
              std::to_string(bytes.size()) + " bytes");
  if (num_faces > bound || num_faces > kMaxMeshElements)
    scan.fail("face count " + std::to_string(num_faces) + " too large for a file of " +
              std::to_string(bytes.size()) + " bytes");
  if (num_faces == 0) throw Error(name + ": no faces");

  MeshBuilder builder;
  builder.reserve(num_vertices, num_faces);
  for (std::int64_t v = 0; v < num_vertices; ++v) {
    if (!scan.next_content_line())
      throw Error(name + ": truncated: file ends at vertex " + std::to_string(v) + " of " +
                  std::to_string(num_vertices));
    const double x = scan.read_double("x coordinate");
    const double y = scan.read_double("y coordinate");
    const double z = scan.read_double("z coordinate");
    builder.add_vertex(x, y, z);
  }
  std::vector<int> polygon;
  for (std::int64_t f = 0; f < num_faces; ++f) {
    if (!scan.next_content_line())
      throw Error(name + ": truncated: file ends at face " + std::to_string(f) + " of " +
                  std::to_string(num_faces));
    const std::int64_t n = scan.read_int("face vertex count");
    if (n < 3) scan.fail("face " + std::to_string(f) + " has " + std::to_string(n) + " vertices (needs at least 3)");
    if (n > static_cast<std::int64_t>(scan.bytes_left() + 1024))
      scan.fail("face " + std::to_string(f) + " vertex count " + std::to_string(n) + " too large");
    polygon.clear();
    for (std::int64_t k = 0; k < n; ++k) {
      const std::int64_t index = scan.read_int("face index");
      if (index < 0 || index >= num_vertices)
        scan.fail("face index " + std::to_string(index) + " out of range (" + std::to_string(num_vertices) +
                  " vertices)");
      polygon.push_back(static_cast<int>(index));
    }
    builder.add_polygon(polygon.data(), polygon.size());
  }
  return builder.finish(name);
}

std::string serialize_off(const mesh::TriangleMesh& mesh) {
  std::string out = "OFF\n";
  append_number(out, static_cast<long long>(mesh.num_vertices()));
  out += ' ';
  append_number(out, static_cast<long long>(mesh.num_faces()));
  out += " 0\n";
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    for (int k = 0; k < 3; ++k) {
      if (k > 0) out += ' ';
      append_number(out, mesh.positions(v, k));
    }
    out += '\n';
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    out += '3';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, static_cast<long long>(mesh.triangles(f, k)));
    }
    out += '\n';
  }
  return out;
}

}  // namespace volspline::io
