// SPDX-License-Identifier: MIT
#pragma once

#include <emscripten/val.h>

#include <string>

namespace volspline::wasm {

/// JS: mesh2spline(bytes, name, options, progress) -> {ok:true, ...} or {ok:false, message}.
///   bytes    Uint8Array|ArrayBuffer of a mesh file, format from `name`'s extension
///            (OBJ, OFF, PLY, STL, GLB); `name` also prefixes error messages;
///   options  plain object, every key optional. Job (pipeline::Mesh2SplineOptions): max_rms_rel,
///            max_control_points, max_levels, fit ('grid'|'meshless'), weights
///            ('meanvalue'|'cotan'), initial_cells, grid_nodes, smoothing, seed, measure_samples,
///            corners (8 vertex ids), max_surface_error_rel (> 0), area_balance_iterations ([0, 20]),
///            min_scaled_jacobian (Jacobian repair target: 0 = off, else (0, 0.5]), threads (≥ 1; accepted, the job runs on one thread),
///            compare_uniform (boolean: also fit uniform B-splines, stats uniform_*). View: preview_samples (boundary lattice per face, default
///            25, [2, 129]), preview_lines (iso-lines per direction per face, default 9, [2, 65]),
///            cut_axis (0|1|2, default 2), cut_position ([0, 1], default 0.5), cut_samples
///            (default 41, [2, 257]), vtu_cells (per axis, default 24, [1, 64]), outputs
///            (boolean, default true: also serialize JSON, GLB and VTU);
///   progress function (stage, fraction) -> boolean or undefined/null; false cancels
///            ({ok:false, message:'cancelled'}).
/// Output: stats (the keys of the CLI's stats JSON, times_s with a total), input {positions
/// Float32Array, triangles Uint32Array, bbox_min, bbox_max}, boundary {positions, uvw, triangles},
/// lines {positions, uvw} (segments), control_points Float32Array, cut {axis, position, positions,
/// triangles, scaled_jacobian Float32Array, min_scaled_jacobian}, and with outputs:
/// spline_json, glb, vtu as Uint8Array (the bytes the CLI writes for -o, --glb, --vtk).
emscripten::val mesh2spline(const emscripten::val& bytes, const std::string& name, const emscripten::val& options,
                            const emscripten::val& progress);

/// JS: splineCut(splineJson, axis, position, samples) -> {ok:true, axis, position, positions,
/// triangles, scaled_jacobian, min_scaled_jacobian} or {ok:false, message}: the cut of a spline
/// JSON document (Uint8Array|ArrayBuffer, as returned by mesh2spline) at uvw[axis] = position
/// (fraction of the domain), sampled samples×samples.
emscripten::val spline_cut(const emscripten::val& spline_json, int axis, double position, int samples);

}  // namespace volspline::wasm
