// SPDX-License-Identifier: MIT
#pragma once

#include <emscripten/val.h>

#include <string>

namespace volspline::wasm {

/// JS: gpc(bytes, name, options, progress) -> {ok:true, ...} or {ok:false, message}.
///   bytes    Uint8Array|ArrayBuffer of a mesh file, format from `name`'s extension
///            (OBJ, OFF, PLY, STL, GLB); `name` also prefixes error messages;
///   options  plain object, every key optional (pipeline::GpcOptions): grid_nodes (about this
///            many volumetric grid nodes over all cuboids, default 24000, [64, 2e7]), untangle
///            (boolean, default true: remove the harmonic grid's folds), corners (8 vertex ids of a
///            genus-0 solid's cuboid), snap ([0, 0.45)), merge_cuboids (boolean, default true:
///            merge cuboids glued end to end across cuts), limb_persistence (limb ends become
///            caps: fraction of the graph diameter in [0, 1), 0 = off, negative (default) =
///            automatic, the CLI's --limbs), threads (≥ 1), outputs (boolean,
///            default true: also serialize DOMAIN.json and the segmented GLB);
///   progress function (stage, fraction) -> boolean or undefined/null; false cancels
///            ({ok:false, message:'cancelled'}).
/// Output: stats (the object of `volspline gpc --stats-json`: genus, t_shapes, tubes, caps,
/// cuboids, ill_points, flipped_triangles, grid_inverted_hexes, grid_min_scaled_jacobian, ...,
/// times_s with a total), surface {positions Float32Array (3 points of 3 floats per triangle, model
/// units), colours Float32Array (RGB in [0, 1] per point, io::segment_colour of its cuboid),
/// face_cuboid Uint32Array (per triangle)} of the input surface refined along the cuts,
/// poly_edges Float32Array (line segments, 2 points each), corners Float32Array (8 points per
/// cuboid), bbox_min, bbox_max [x, y, z]; with outputs: domain_json (UTF-8 bytes of DOMAIN.json)
/// and glb (the segmented GLB), as Uint8Array, the bytes the CLI writes for -o and --glb.
/// A construction that fails (a cut that is no meridian, a layout that cannot be traced) gives
/// {ok:false, message:'gpc failed: ...'}.
emscripten::val gpc(const emscripten::val& bytes, const std::string& name, const emscripten::val& options,
                    const emscripten::val& progress);

}  // namespace volspline::wasm
