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
/// spline_json, glb, vtu as Uint8Array (the bytes the CLI writes for -o, --glb, --vtk); domain
/// 'cuboid'.
/// A solid of genus > 0 runs pipeline::run_gpc_mesh2spline instead (as the CLI does), domain
/// 'gpc': the keys max_rms_rel, max_control_points, max_levels and max_surface_error_rel (these
/// two only if given: the GPC job's own defaults otherwise, as the CLI), initial_cells,
/// measure_samples, seed, area_balance_iterations, untangle reach it, plus gpc_grid_nodes (grid
/// nodes over all cuboids, default 24000), padding (boolean, default true), adaptive_knots
/// (boolean, default false), adaptive_growth, surface_weight, measure_lattice (the CLI's
/// --knot-growth, --surface-weight, --measure-lattice; ranges checked by the job); fit
/// 'meshless' is refused. Stats are the CLI's GPC stats keys (cuboids, ill_points, t_shapes,
/// genus, interfaces, interface_gap_rel, lattice_negative_fraction, knot_refinement,
/// level_history [{control_points, rms_rel, surface_max_rel}], ...); boundary and lines cover the cuboids' surface faces with uvw as fractions of each
/// cuboid's box, plus cuboid (Uint32Array, per point / per segment) and boundary.colours
/// (Float32Array RGB per point, the GPC view's cuboid colours); control_uvw (Float32Array, each
/// control point's anchor as a fraction of its cuboid's box); the cut is the plane
/// uvw[cut_axis] = cut_position of every cuboid, with cut.cuboid per point; spline_json is the
/// volspline-gpc-spline document, vtu the sampled hexes (vtu_cells per unit of the longest cuboid).
/// A GPC construction that fails on a valid solid gives {ok:false, message:'mesh2spline failed: ...'}.
emscripten::val mesh2spline(const emscripten::val& bytes, const std::string& name, const emscripten::val& options,
                            const emscripten::val& progress);

/// JS: splineCut(splineJson, axis, position, samples) -> {ok:true, axis, position, positions,
/// triangles, scaled_jacobian, min_scaled_jacobian} or {ok:false, message}: the cut of a spline
/// JSON document (Uint8Array|ArrayBuffer, as returned by mesh2spline) at uvw[axis] = position
/// (fraction of the domain), sampled samples×samples. A volspline-gpc-spline document gives the
/// cut of every cuboid at its own uvw[axis] = position, with cuboid (Uint32Array per point).
emscripten::val spline_cut(const emscripten::val& spline_json, int axis, double position, int samples);

}  // namespace volspline::wasm
