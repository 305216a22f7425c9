// SPDX-License-Identifier: MIT
// libFuzzer target: parse_mesh on arbitrary bytes as OFF must return a mesh or throw
// volspline::Error; anything else (crash, sanitizer report, other exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/common/error.h"
#include "core/io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const auto mesh = volspline::io::parse_mesh(bytes, volspline::io::MeshFormat::Off, "fuzz.off");
    // Every reader promises in-range ids and finite coordinates.
    if (mesh.num_faces() == 0 || mesh.triangles.minCoeff() < 0 || mesh.triangles.maxCoeff() >= mesh.num_vertices() ||
        !mesh.positions.allFinite())
      __builtin_trap();
  } catch (const volspline::Error&) {
  }
  return 0;
}
