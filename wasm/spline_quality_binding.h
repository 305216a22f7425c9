// SPDX-License-Identifier: MIT
#pragma once
// splineQuality: the quality views of a geometric spline for the Mesh tab (scaled-Jacobian
// histogram, folded points, distance from the boundary to the input mesh).
#include <emscripten/val.h>

#include <string>

namespace volspline::wasm {

/// splineQuality(splineJson, meshBytes|null, meshName, options) ->
///   {ok, samples, bins, counts: [bins], min_scaled_jacobian, folded: Float32Array (xyz of the
///    lattice points with scaled J ≤ 0), boundary_distance_rel: Float32Array | null (per vertex of
///    the boundary preview, ÷ the mesh's bbox diagonal), max_distance_rel}
/// The scaled Jacobian det J / (|J_u| |J_v| |J_w|) is taken at the centres of an n³ lattice of the
/// domain (options.lattice, default 24, in [2, 96]) and binned over [−1, 1] (options.bins,
/// default 20, in [2, 200]). The boundary preview is spline_preview's with options.preview_samples
/// and options.preview_lines (defaults 25 and 9, as mesh2spline's). A volspline-gpc-spline
/// document is sampled on the lattice of every cuboid (samples = cuboids·n³, plus cuboids), its
/// boundary preview is mesh2spline's for genus > 0. {ok:false, message} on bad JSON, mesh or options.
emscripten::val spline_quality(const emscripten::val& spline_json, const emscripten::val& mesh_bytes,
                               const std::string& mesh_name, const emscripten::val& options);

}  // namespace volspline::wasm
