// SPDX-License-Identifier: MIT
#pragma once

#include <emscripten/val.h>

#include <string>

namespace volspline::wasm {

/// JS: vol2spline(volume, name, options, progress) -> {ok:true, stats, reconstruction,
/// spline_json} or {ok:false, message}.
///   volume   {nx, ny, nz, spacing?: [x,y,z], origin?: [x,y,z], direction?: [9], samples: Float32Array
///            (x fastest)}, as loadVolume
///            returns it;
///   options  plain object, every key optional (pipeline::Vol2SplineOptions): max_rms_rel,
///            max_control_points, max_levels, initial_cells, param ('identity'|'aligned'),
///            compute_frames (boolean), clusters, iso; outputs (boolean, default true: the
///            spline JSON);
///   progress function (stage, fraction) -> boolean or undefined/null; false cancels.
/// Output: stats (the keys of pipeline::Vol2SplineStats, curve as [{control_points, rms_rel,
/// max_rel}], times_s with a total), reconstruction Float32Array (the spline's density at every
/// voxel, x fastest), spline_json Uint8Array (D = 4: X, Y, Z, density).
emscripten::val vol2spline(const emscripten::val& volume, const std::string& name, const emscripten::val& options,
                           const emscripten::val& progress);

}  // namespace volspline::wasm
