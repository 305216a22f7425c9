// SPDX-License-Identifier: MIT
#include "wasm/vol2spline_binding.h"

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/common/error.h"
#include "core/io/spline_json.h"
#include "core/pipeline/vol2spline_job.h"
#include "wasm/guarded.h"
#include "wasm/js_values.h"

namespace volspline::wasm {

using emscripten::val;

namespace {

int integer_option(const val& o, const char* key, int fallback) {
  const double x = number_option(o, key, fallback);
  if (x != static_cast<double>(static_cast<long long>(x)) || std::abs(x) > 1e9)
    throw Error(std::string("option '") + key + "': expected an integer");
  return static_cast<int>(x);
}

volume::Volume volume_from_js(const val& v, const std::string& name) {
  if (v.isUndefined() || v.isNull() || v.typeOf().as<std::string>() != "object")
    throw Error(name + ": expected a volume {nx, ny, nz, samples}");
  volume::Volume out;
  int* dims[3] = {&out.nx, &out.ny, &out.nz};
  const char* keys[3] = {"nx", "ny", "nz"};
  for (int k = 0; k < 3; ++k) {
    const double d = number_option(v, keys[k], -1);
    if (!(d >= 1 && d <= 1 << 20) || d != static_cast<int>(d))
      throw Error(name + ": '" + keys[k] + "' must be a positive integer");
    *dims[k] = static_cast<int>(d);
  }
  const val spacing = v["spacing"];
  if (spacing.isArray() && spacing["length"].as<int>() == 3)
    for (int k = 0; k < 3; ++k) out.spacing[k] = spacing[k].as<double>();
  const val origin = v["origin"];
  if (origin.isArray() && origin["length"].as<int>() == 3)
    for (int k = 0; k < 3; ++k) out.origin[k] = origin[k].as<double>();
  const val direction = v["direction"];  // column-major: axis a's direction is [3a, 3a + 3)
  if (direction.isArray() && direction["length"].as<int>() == 9)
    for (int k = 0; k < 9; ++k) out.direction(k % 3, k / 3) = direction[k].as<double>();
  const val samples = v["samples"];
  if (samples.isUndefined() || samples.isNull() || !samples.instanceof(val::global("Float32Array")))
    throw Error(name + ": 'samples' must be a Float32Array");
  const std::size_t n = samples["length"].as<std::size_t>();
  if (n != out.num_voxels())
    throw Error(name + ": samples has " + std::to_string(n) + " values, expected nx*ny*nz = " +
                std::to_string(out.num_voxels()));
  out.samples.resize(n);
  if (n > 0) {
    // No allocation between making the view and filling it, so the heap cannot move.
    val view(emscripten::typed_memory_view(n, out.samples.data()));
    view.call<void>("set", samples);
  }
  return out;
}

pipeline::Vol2SplineOptions options_from_js(const val& o) {
  pipeline::Vol2SplineOptions options;
  options.max_rms_rel = number_option(o, "max_rms_rel", options.max_rms_rel);
  options.max_control_points = integer_option(o, "max_control_points", options.max_control_points);
  options.max_levels = integer_option(o, "max_levels", options.max_levels);
  options.min_gain_rate = number_option(o, "min_gain_rate", options.min_gain_rate);
  options.initial_cells = integer_option(o, "initial_cells", options.initial_cells);
  options.clusters = integer_option(o, "clusters", options.clusters);
  if (bool_option(o, "compute_frames", false)) options.compute_frames = pipeline::Vol2SplineOptions::ComputeFrames::On;
  options.iso = number_option(o, "iso", options.iso);  // a missing key keeps NaN (no threshold)
  const std::string param = string_option(o, "param", "identity");
  if (param == "identity") options.param = pipeline::Vol2SplineParam::Identity;
  else if (param == "aligned") options.param = pipeline::Vol2SplineParam::Aligned;
  else throw Error("option 'param': unknown '" + param + "' (identity, aligned)");
  return options;  // ranges are checked by run_vol2spline
}

val stats_to_js(const pipeline::Vol2SplineStats& s, const std::string& name) {
  val out = val::object();
  out.set("input", name);
  out.set("density_rms_rel", s.density_rms_rel);
  out.set("density_max_rel", s.density_max_rel);
  out.set("control_points", s.control_points);
  out.set("voxels", static_cast<double>(s.voxels));
  out.set("patches", s.patches);
  out.set("corners", s.corners);
  out.set("levels", s.levels);
  out.set("max_control_points", s.max_control_points);
  out.set("stop_reason", s.stop_reason);
  out.set("clusters", s.clusters);
  out.set("constraints", s.constraints);
  out.set("frames_computed", s.frames_computed);
  out.set("frame_smoothness_initial", s.frame_smoothness_initial);
  out.set("frame_smoothness_final", s.frame_smoothness_final);
  out.set("frame_iterations", s.frame_iterations);
  out.set("constraint_angle_max_deg", s.constraint_angle_max_deg);
  out.set("min_scaled_jacobian", s.min_scaled_jacobian);
  out.set("param_min_jacobian", s.param_min_jacobian);
  out.set("param_inverted_cells", s.param_inverted_cells);
  val curve = val::array();
  for (const auto& level : s.curve) {
    val l = val::object();
    l.set("control_points", level.control_points);
    l.set("rms_rel", level.rms_rel);
    l.set("max_rel", level.max_rel);
    curve.call<void>("push", l);
  }
  out.set("curve", curve);
  out.set("times_s", stage_times_object(s.times_s));
  return out;
}

}  // namespace

val vol2spline(const val& volume, const std::string& name, const val& options, const val& progress) {
  return guarded([&] {
    const pipeline::Vol2SplineOptions job = options_from_js(options);
    const bool outputs = bool_option(options, "outputs", true);
    const volume::Volume input = volume_from_js(volume, name);
    const pipeline::Vol2SplineResult result = pipeline::run_vol2spline(input, name, job, progress_from_js(progress));
    val out = val::object();
    out.set("ok", true);
    out.set("stats", stats_to_js(result.stats, name));
    const std::vector<float> density(result.reconstruction.begin(), result.reconstruction.end());
    out.set("reconstruction", float32_array(density.data(), density.size()));
    if (outputs) {
      const std::string json = io::serialize_spline_json(result.spline);
      out.set("spline_json", uint8_array(reinterpret_cast<const std::uint8_t*>(json.data()), json.size()));
    }
    return out;
  });
}

}  // namespace volspline::wasm
