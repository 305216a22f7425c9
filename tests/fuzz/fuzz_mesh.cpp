// SPDX-License-Identifier: MIT
// libFuzzer target: parse_mesh on arbitrary bytes must return a mesh or throw volspline::Error;
// anything else (crash, sanitizer report, other exception) is a bug. One source for every mesh
// reader: VOLSPLINE_FUZZ_MESH_FILE ("fuzz.obj", "fuzz.gltf", ...) names the input, and its
// extension picks the format.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/common/error.h"
#include "core/io/mesh_io.h"

#ifndef VOLSPLINE_FUZZ_MESH_FILE
#error "define VOLSPLINE_FUZZ_MESH_FILE, e.g. \"fuzz.obj\""
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const std::string name = VOLSPLINE_FUZZ_MESH_FILE;
  const volspline::io::MeshFormat format = volspline::io::mesh_format_from_path(name);
  try {
    const auto mesh = volspline::io::parse_mesh(bytes, format, name);
    // Every reader promises in-range ids and finite coordinates.
    if (mesh.num_faces() == 0 || mesh.triangles.minCoeff() < 0 || mesh.triangles.maxCoeff() >= mesh.num_vertices() ||
        !mesh.positions.allFinite())
      __builtin_trap();
  } catch (const volspline::Error&) {
  }
  return 0;
}
