// SPDX-License-Identifier: MIT
#pragma once

#include <optional>
#include <string>

#include "core/mesh/triangle_mesh.h"

namespace volspline::io {

/// Parses glTF 2.0, JSON (.gltf) or binary (.glb, recognised by its "glTF" magic), with
/// tinygltf. Every TRIANGLES primitive of every mesh instance in the default scene (or, with no
/// scenes, under every root node; with no nodes, every mesh once) is appended with its node's
/// world transform applied; vertices are not merged. Indices may have any integer component
/// type; primitives without indices use consecutive vertex triples.
/// `base_dir`: folder for external buffer URIs; without it only embedded data (data: URIs, the
/// GLB BIN chunk) is allowed, so parsing from memory never touches files.
/// Throws volspline::Error naming `name` and the mesh/primitive/accessor on: invalid glTF,
/// accessors outside their buffers, sparse accessors, indices out of range, index counts not a
/// multiple of 3, non-finite positions, node cycles, no triangles.
mesh::TriangleMesh parse_gltf(const std::string& bytes, const std::string& name,
                              const std::optional<std::string>& base_dir = std::nullopt);

/// glTF 2.0 binary (GLB): one node, one mesh, one TRIANGLES primitive with a float32 VEC3
/// POSITION accessor (with min/max) and uint32 indices. Positions are rounded to float32, the
/// only POSITION type glTF allows. Throws volspline::Error if a coordinate exceeds float range.
std::string serialize_glb(const mesh::TriangleMesh& mesh);

}  // namespace volspline::io
