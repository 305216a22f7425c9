// SPDX-License-Identifier: MIT
#pragma once

#include <emscripten/val.h>

#include <string>

namespace volspline::wasm {

/// JS: meshInfo(bytes: Uint8Array|ArrayBuffer, name: string) ->
///   {ok:true, vertices, faces, edges, closed, manifold, boundary_loops, components,
///    consistently_oriented, degenerate_faces, euler_characteristic, genus (null if undefined),
///    signed_volume, bbox_min [x,y,z], bbox_max [x,y,z],
///    positions: Float32Array (3 per vertex, model units),
///    triangles: Uint32Array (3 per face, consistently oriented as HalfedgeMesh stores them)}
/// or {ok:false, message}. The format comes from the extension of `name` (obj off ply stl gltf glb);
/// the message names `name` and the first bad element (parse error, non-manifold, ...).
emscripten::val mesh_info(const emscripten::val& bytes, const std::string& name);

}  // namespace volspline::wasm
