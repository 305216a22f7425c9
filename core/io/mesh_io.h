// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/mesh/triangle_mesh.h"

namespace volspline::io {

/// Mesh file formats that volspline reads and (except Stl, Gltf) writes.
enum class MeshFormat { Obj, Off, Ply, Stl, Gltf, Glb };

/// Format from a file name's extension (obj, off, ply, stl, gltf, glb).
/// Throws volspline::Error naming the path if the extension is unknown.
MeshFormat mesh_format_from_path(const std::string& path);

/// Parses a mesh held in memory. `name` is used in error messages (a path or an upload name).
/// Polygons are fan-triangulated. Throws volspline::Error naming `name` and the line or element
/// on: truncation, bad counts, indices out of range, NaN/Inf coordinates, no faces.
mesh::TriangleMesh parse_mesh(const std::string& bytes, MeshFormat format, const std::string& name);

/// Reads a mesh file; the format comes from the extension (PLY/STL: ASCII or binary).
mesh::TriangleMesh read_mesh(const std::string& path);

/// Serializes a mesh (Obj, Off, Ply as binary little-endian, Glb) with round-trip precision.
std::string serialize_mesh(const mesh::TriangleMesh& mesh, MeshFormat format);

/// Writes a mesh atomically; the format comes from the extension (obj, off, ply, glb).
void write_mesh(const std::string& path, const mesh::TriangleMesh& mesh);

}  // namespace volspline::io
