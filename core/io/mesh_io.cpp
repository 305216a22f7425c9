// SPDX-License-Identifier: MIT
#include "core/io/mesh_io.h"

#include "core/common/error.h"
#include "core/io/file_bytes.h"
#include "core/io/gltf_format.h"
#include "core/io/obj_format.h"
#include "core/io/off_format.h"
#include "core/io/ply_format.h"
#include "core/io/stl_format.h"

namespace volspline::io {

MeshFormat mesh_format_from_path(const std::string& path) {
  const std::string ext = file_extension(path);
  if (ext == "obj") return MeshFormat::Obj;
  if (ext == "off") return MeshFormat::Off;
  if (ext == "ply") return MeshFormat::Ply;
  if (ext == "stl") return MeshFormat::Stl;
  if (ext == "gltf") return MeshFormat::Gltf;
  if (ext == "glb") return MeshFormat::Glb;
  throw Error(path + ": unknown mesh file extension '" + ext + "' (expected obj, off, ply, stl, gltf or glb)");
}

mesh::TriangleMesh parse_mesh(const std::string& bytes, MeshFormat format, const std::string& name) {
  switch (format) {
    case MeshFormat::Obj: return parse_obj(bytes, name);
    case MeshFormat::Off: return parse_off(bytes, name);
    case MeshFormat::Ply: return parse_ply(bytes, name);
    case MeshFormat::Stl: return parse_stl(bytes, name);
    case MeshFormat::Gltf:
    case MeshFormat::Glb: return parse_gltf(bytes, name);
  }
  throw Error(name + ": unknown mesh format");
}

mesh::TriangleMesh read_mesh(const std::string& path) {
  refuse_special_file(path);
  const MeshFormat format = mesh_format_from_path(path);
  const std::string bytes = read_file_bytes(path);
  if (format == MeshFormat::Gltf || format == MeshFormat::Glb) {
    // External buffers of a .gltf are resolved next to the file.
    const auto slash = path.find_last_of("/\\");
    return parse_gltf(bytes, path, slash == std::string::npos ? std::string(".") : path.substr(0, slash));
  }
  return parse_mesh(bytes, format, path);
}

std::string serialize_mesh(const mesh::TriangleMesh& mesh, MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj: return serialize_obj(mesh);
    case MeshFormat::Off: return serialize_off(mesh);
    case MeshFormat::Ply: return serialize_ply(mesh);
    case MeshFormat::Glb: return serialize_glb(mesh);
    case MeshFormat::Stl:
    case MeshFormat::Gltf: break;
  }
  throw Error("writing this mesh format is not supported (write obj, off, ply or glb)");
}

void write_mesh(const std::string& path, const mesh::TriangleMesh& mesh) {
  const MeshFormat format = mesh_format_from_path(path);
  if (format == MeshFormat::Stl || format == MeshFormat::Gltf)
    throw Error(path + ": writing ." + file_extension(path) + " is not supported (write obj, off, ply or glb)");
  write_file_atomic(path, serialize_mesh(mesh, format));
}

}  // namespace volspline::io
