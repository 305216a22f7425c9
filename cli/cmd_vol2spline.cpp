// SPDX-License-Identifier: MIT
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/output_files.h"
#include "cli/progress_bar.h"
#include "cli/stage_times_json.h"
#include "core/io/file_bytes.h"
#include "core/io/spline_json.h"
#include "core/io/volume_io.h"
#include "core/io/bezier_vtu_writer.h"
#include "core/io/volume_vti_writer.h"
#include "core/io/volume_vtu_writer.h"
#include "core/linalg/parallel_for.h"
#include "core/pipeline/vol2spline_job.h"

namespace volspline::cli {

namespace {

std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, ',')) parts.push_back(part);
  return parts;
}

double parse_number(const std::string& text, const std::string& option) {
  std::size_t used = 0;
  double x = 0.0;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(x))
    throw UsageError("--" + option + ": '" + text + "' is not a number");
  return x;
}

std::array<double, 3> parse_triple(const std::string& text, const std::string& option) {
  const std::vector<std::string> parts = split_commas(text);
  if (parts.size() != 3) throw UsageError("--" + option + " needs three comma-separated numbers, got '" + text + "'");
  return {parse_number(parts[0], option), parse_number(parts[1], option), parse_number(parts[2], option)};
}

// Corner voxels: one "x y z" voxel coordinate triple per line.
std::vector<std::size_t> read_corners(const std::string& path, const volume::Volume& v) {
  std::istringstream in(io::read_file_bytes(path));
  std::vector<long long> numbers;
  std::string token;
  while (in >> token) {
    std::size_t used = 0;
    long long x = -1;
    try {
      x = std::stoll(token, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != token.size() || x < 0)
      throw Error("corners file '" + path + "': '" + token + "' is not a voxel coordinate");
    numbers.push_back(x);
  }
  if (numbers.empty() || numbers.size() % 3 != 0)
    throw Error("corners file '" + path + "': expected lines of 'x y z' voxel coordinates");
  std::vector<std::size_t> ids;
  for (std::size_t i = 0; i < numbers.size(); i += 3) {
    if (numbers[i] >= v.nx || numbers[i + 1] >= v.ny || numbers[i + 2] >= v.nz)
      throw Error("corners file '" + path + "': voxel (" + std::to_string(numbers[i]) + ", " +
                  std::to_string(numbers[i + 1]) + ", " + std::to_string(numbers[i + 2]) + ") is outside the " +
                  std::to_string(v.nx) + "x" + std::to_string(v.ny) + "x" + std::to_string(v.nz) + " volume");
    ids.push_back(v.index(static_cast<int>(numbers[i]), static_cast<int>(numbers[i + 1]), static_cast<int>(numbers[i + 2])));
  }
  return ids;
}

}  // namespace

// Longer than the guide's ~120 lines on purpose: a flat driver (the option table, flags →
// options, the job, the outputs) with nothing to reuse; split, every part would take the parsed
// arguments and the output list along.
int run_vol2spline(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = with_job_options({
      {"output", "OUT.json", "spline JSON of (X, Y, Z, density), dimension 4 (required; also -o)"},
      {"vtk", "OUT.vtu", "the (X, Y, Z, density) spline as VTK Bézier hexahedra (exact; point data density)"},
      {"vti", "OUT.vti", "the voxels as VTK ImageData: sample, reconstructed density, error (and uvw if aligned)"},
      {"frames-vtk", "F.vtu", "smoothed frame field: one vertex per voxel with axes f0, f1, f2"},
      {"dims", "X,Y,Z", "raw volumes: voxels per axis (default: from a name like fuel_64x64x64_uint8.raw)"},
      {"type", "T", "raw volumes: uint8|int8|uint16|int16|uint32|int32|float32|float64 (default uint8)"},
      {"spacing", "SX,SY,SZ", "voxel size, overrides the file's (default 1,1,1 for raw)"},
      {"max-rms", "R", "stop refining at density RMS <= R (fraction of the density range; default 0.005)"},
      {"max-control-points", "N", "the spline never has more control points (default: voxels/16, within 64..50000)"},
      {"max-levels", "L", "refinement levels after level 0 (default 10)"},
      {"min-gain-rate", "R", "stop after a level with ln(rms ratio)/ln(control point ratio) < R (default 0.25; 0 = off)"},
      {"initial-cells", "N", "level-0 cells along the longest axis (default longest/8)"},
      {"param", "identity|aligned", "identity: plain voxel grid; aligned: frame-field-aligned (default identity)"},
      {"clusters", "K", "k-means materials, 2..16 (default automatic)"},
      {"iso", "V", "classify by the threshold V (sample units) instead of k-means"},
      {"corners", "FILE", "corner voxels, one 'x y z' per line (aligned; default automatic)"},
      {"max-voxels", "N", "refuse volumes of more voxels, checked on the header before reading (default 16777216 = 256^3)"},
  }, "worker threads (default: the cores, at most 8; same output for any N)");
  const Args args = parse_args(argv, specs);
  if (print_help_if_asked(args, "volspline vol2spline VOLUME -o OUT.json [options]",
                          "Fits a trivariate T-spline of (X, Y, Z, density) to a scalar volume (raw, NRRD/NHDR,\n"
                          "legacy VTK structured points, MetaImage) with adaptive refinement (thesis ch. 5).\n"
                          "--param aligned first builds the Hessian frame field, classifies materials, smooths the\n"
                          "frames and computes the field-aligned parameterization. Refinement stops at the first of:\n"
                          "--max-rms reached (stop_reason target), the control point budget (budget), a level that\n"
                          "gains too little, ln(rms ratio)/ln(control point ratio) < --min-gain-rate or < 2 %\n"
                          "(diminishing), --max-levels (max_levels), no cell left to split (no_cells). A level is only\n"
                          "started if the budget leaves room for 25 % more control points. Exit 2 on bad input.",
                          specs))
    return 0;
  if (args.positional.size() != 1) throw UsageError("expects exactly one VOLUME (see --help)");
  const std::string output = args.get("output");
  if (output.empty()) throw UsageError("needs -o OUT.json");

  pipeline::Vol2SplineOptions options;
  options.max_rms_rel = args.get_double("max-rms", options.max_rms_rel);
  options.max_control_points = args.get_int("max-control-points", options.max_control_points);
  options.max_levels = args.get_int("max-levels", options.max_levels);
  options.min_gain_rate = args.get_double("min-gain-rate", options.min_gain_rate);
  options.initial_cells = args.get_int("initial-cells", options.initial_cells);
  options.threads = args.get_int("threads", linalg::default_thread_count());
  options.clusters = args.get_int("clusters", options.clusters);
  if (args.has("iso")) options.iso = args.get_double("iso", 0.0);
  const std::string param = args.get("param", "identity");
  if (param == "identity")
    options.param = pipeline::Vol2SplineParam::Identity;
  else if (param == "aligned")
    options.param = pipeline::Vol2SplineParam::Aligned;
  else
    throw UsageError("--param must be identity or aligned, got '" + param + "'");
  if (args.has("frames-vtk")) options.compute_frames = pipeline::Vol2SplineOptions::ComputeFrames::On;

  io::VolumeReadOptions read;
  if (args.has("max-voxels")) {
    const double max_voxels = args.get_double("max-voxels", 0.0);
    if (!(max_voxels >= 1) || max_voxels != std::floor(max_voxels) || max_voxels > 9e15)
      throw UsageError("--max-voxels expects a positive integer, got '" + args.get("max-voxels") + "'");
    read.max_voxels = static_cast<std::int64_t>(max_voxels);
  }
  const std::string& path = args.positional[0];
  if (args.has("dims") || args.has("type")) {
    io::RawVolumeLayout layout;
    if (!args.has("dims")) throw UsageError("--type needs --dims X,Y,Z");
    const std::array<double, 3> dims = parse_triple(args.get("dims"), "dims");
    for (int a = 0; a < 3; ++a) {
      if (dims[a] < 1 || dims[a] != std::floor(dims[a]) || dims[a] > 1e5)
        throw UsageError("--dims needs positive integers, got '" + args.get("dims") + "'");
      layout.dims[a] = static_cast<int>(dims[a]);
    }
    layout.type = io::sample_type_from_name(args.get("type", "uint8"));
    read.raw_layout = layout;
  }
  OutputFiles files;
  files.input(path);
  if (args.has("corners")) files.input(args.get("corners"));
  files.output("-o", output);
  for (const char* flag : {"vtk", "vti", "frames-vtk", "stats-json"})
    if (args.has(flag)) files.output(std::string("--") + flag, args.get(flag));
  volume::Volume vol = io::read_volume(path, read);
  if (args.has("spacing")) {
    const std::array<double, 3> s = parse_triple(args.get("spacing"), "spacing");
    for (int a = 0; a < 3; ++a) {
      if (!(s[a] > 0.0)) throw UsageError("--spacing values must be positive");
      vol.spacing(a) = s[a];
    }
  }
  if (args.has("corners")) options.corners = read_corners(args.get("corners"), vol);

  ProgressBar bar(!args.has("quiet"));
  const pipeline::Vol2SplineResult result = pipeline::run_vol2spline(vol, path, options, bar.progress());
  bar.finish();

  files.stage(output, io::serialize_spline_json(result.spline));
  if (args.has("vtk")) files.stage(args.get("vtk"), io::serialize_bezier_vtu(result.spline));
  if (args.has("vti")) files.stage(args.get("vti"), io::serialize_density_vti(vol, result.reconstruction, result.uvw));
  if (args.has("frames-vtk")) files.stage(args.get("frames-vtk"), io::serialize_frames_vtu(vol, result.frames));
  const pipeline::Vol2SplineStats& s = result.stats;
  if (args.has("stats-json")) {
    nlohmann::ordered_json j;
    auto frame_value = [&](double x) {
      return s.frames_computed ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
    };
    j["input"] = path;
    j["param"] = param;
    j["density_rms_rel"] = s.density_rms_rel;
    j["density_max_rel"] = s.density_max_rel;
    j["control_points"] = s.control_points;
    j["voxels"] = s.voxels;
    j["patches"] = s.patches;
    j["corners"] = s.corners;
    j["levels"] = s.levels;
    j["stop_reason"] = s.stop_reason;
    j["max_control_points"] = s.max_control_points;
    j["clusters"] = s.clusters;
    j["constraints"] = s.constraints;
    j["frame_smoothness_initial"] = frame_value(s.frame_smoothness_initial);
    j["frame_smoothness_final"] = frame_value(s.frame_smoothness_final);
    j["frame_iterations"] = s.frame_iterations;
    j["constraint_angle_max_deg"] = frame_value(s.constraint_angle_max_deg);
    j["min_scaled_jacobian"] = s.min_scaled_jacobian;
    j["param_min_jacobian"] = s.param_min_jacobian;
    j["param_inverted_cells"] = s.param_inverted_cells;
    j["spline_bytes_binary"] = static_cast<long long>(s.control_points) * 4 * 8;
    nlohmann::ordered_json curve = nlohmann::ordered_json::array();
    for (const auto& level : s.curve)
      curve.push_back({{"control_points", level.control_points}, {"density_rms_rel", level.rms_rel},
                       {"density_max_rel", level.max_rel}, {"cg_iterations", level.cg_iterations}});
    j["curve"] = curve;
    j["times_s"] = stage_times_json(s.times_s);
    files.stage(args.get("stats-json"), j.dump(2) + "\n");
  }
  files.commit();
  if (!args.has("quiet"))
    std::fprintf(stderr, "vol2spline: %d control points, %d levels, density_rms_rel %.4g, density_max_rel %.4g, stopped: %s\n",
                 s.control_points, s.levels, s.density_rms_rel, s.density_max_rel, s.stop_reason.c_str());
  return 0;
}

}  // namespace volspline::cli
