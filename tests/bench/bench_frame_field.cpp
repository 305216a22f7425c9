// SPDX-License-Identifier: MIT
// vol2spline front half on every volume in the shared data folder (or the files given as
// arguments): local cubic fit, Hessian frames, material classification, frame-field smoothing
// on the foreground (+2 voxel margin), corner detection, field-aligned parameterization.
// Prints one JSON object per volume: per-stage wall and CPU (this thread) seconds, medians of
// `runs` runs (argument --runs N, default 3), plus the quality numbers of the last run.
// Other arguments: --anisotropy A (Eq. 5.10 alpha), --margin M (smoothing margin, default 2),
// --no-corners (no corner constraints), --corner-weight W, --given (FrameInitialization::Given: start from the Hessian frames),
// --reliability-radius R, --identity-weight L, --background-weight B (FieldAlignedOptions).
// --fit: also run the scattered adaptive fit (Eq. 5.11) over the map, as `vol2spline --param aligned
// --max-rms 0.001 --min-gain-rate 0` does, and print its curve (--max-control-points N, default
// 15000; --initial-cells N; --identity-map fits over the identity map instead, same fit code).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/io/volume_io.h"
#include "core/spline/scattered_density_fitting.h"
#include "core/volume/corner_detection.h"
#include "core/volume/field_aligned_param.h"
#include "core/volume/frame_field.h"
#include "core/volume/hessian_frames.h"
#include "core/volume/local_cubic_fit.h"
#include "core/volume/material_classification.h"

namespace vol = volspline::volume;
using nlohmann::json;

namespace {

double cpu_now() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

double wall_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 3;
  double anisotropy = vol::FieldAlignedOptions{}.anisotropy;
  bool corners_on = true;
  int margin = 2;
  bool given = false;
  double corner_weight = vol::FieldAlignedOptions{}.corner_weight;
  std::vector<std::string> paths;
  vol::FieldAlignedOptions defaults;
  double reliability_radius = defaults.reliability_radius;
  double identity_weight = defaults.identity_weight;
  double background_weight = defaults.background_weight;
  bool fit_curve = false, identity_map = false;
  int max_control_points = 15000, initial_cells = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--runs" && i + 1 < argc) runs = std::max(1, std::stoi(argv[++i]));
    else if (arg == "--anisotropy" && i + 1 < argc) anisotropy = std::stod(argv[++i]);
    else if (arg == "--margin" && i + 1 < argc) margin = std::stoi(argv[++i]);
    else if (arg == "--no-corners") corners_on = false;
    else if (arg == "--given") given = true;
    else if (arg == "--corner-weight" && i + 1 < argc) corner_weight = std::stod(argv[++i]);
    else if (arg == "--reliability-radius" && i + 1 < argc) reliability_radius = std::stod(argv[++i]);
    else if (arg == "--identity-weight" && i + 1 < argc) identity_weight = std::stod(argv[++i]);
    else if (arg == "--background-weight" && i + 1 < argc) background_weight = std::stod(argv[++i]);
    else if (arg == "--fit") fit_curve = true;
    else if (arg == "--identity-map") identity_map = true;
    else if (arg == "--max-control-points" && i + 1 < argc) max_control_points = std::stoi(argv[++i]);
    else if (arg == "--initial-cells" && i + 1 < argc) initial_cells = std::stoi(argv[++i]);
    else paths.push_back(arg);
  }
  if (paths.empty()) {
    const std::string dir = std::string(VOLSPLINE_SHARED_DATA) + "/volumes/";
    for (const char* name : {"bucky_32x32x32_uint8.raw", "fuel_64x64x64_uint8.raw", "neghip_64x64x64_uint8.raw",
                             "tooth_103x94x161_uint8.raw"})
      paths.push_back(dir + name);
  }
  const char* stages[] = {"fit", "frames", "classify", "smooth", "corners", "param", "total"};
  for (const std::string& path : paths) {
    const vol::Volume volume = volspline::io::read_volume(path);
    std::vector<std::vector<double>> wall(7), cpu(7);
    json quality;
    for (int run = 0; run < runs; ++run) {
      std::vector<double> w, c;
      double w0 = wall_now(), c0 = cpu_now();
      auto lap = [&] {
        const double w1 = wall_now(), c1 = cpu_now();
        w.push_back(w1 - w0);
        c.push_back(c1 - c0);
        w0 = w1;
        c0 = c1;
      };
      const vol::LocalCubicFit fit = vol::fit_local_cubics(volume);
      lap();
      vol::FrameField field{volume.nx, volume.ny, volume.nz, vol::hessian_frames(fit.hessian)};
      lap();
      const vol::MaterialClassification classes = vol::classify_materials(volume, fit);
      lap();
      vol::FrameSmoothingOptions smoothing;
      smoothing.active = vol::foreground_mask(classes, margin);
      if (given) smoothing.initialization = vol::FrameInitialization::Given;
      const vol::FrameSmoothingResult smoothed = vol::smooth_frame_field(field, classes.constraints, smoothing);
      lap();
      const vol::CornerDetection corners = vol::find_corners(smoothed.field, classes);
      lap();
      vol::FieldAlignedOptions param_options;
      param_options.anisotropy = anisotropy;
      param_options.corner_weight = corner_weight;
      param_options.corner_selection = corners_on ? vol::CornerSelection::Given : vol::CornerSelection::None;
      param_options.corner_voxels = corners.corners;
      param_options.reliability_radius = reliability_radius;
      param_options.identity_weight = identity_weight;
      param_options.background_weight = background_weight;
      const vol::FieldAlignedParam param = vol::compute_field_aligned_param(volume, smoothed.field, classes, param_options);
      lap();
      w.push_back(0.0);
      c.push_back(0.0);
      for (int s = 0; s < 6; ++s) {
        w[6] += w[s];
        c[6] += c[s];
      }
      for (int s = 0; s < 7; ++s) {
        wall[s].push_back(w[s]);
        cpu[s].push_back(c[s]);
      }
      std::size_t active = 0;
      for (auto a : smoothing.active) active += a;
      quality = {{"clusters", classes.num_clusters},
                 {"cluster_sizes", classes.cluster_size},
                 {"cluster_mean_intensity", classes.cluster_mean_intensity},
                 {"within_sum_squares", classes.within_sum_squares},
                 {"intensity_unexplained", classes.intensity_unexplained},
                 {"foreground_voxels", classes.num_foreground},
                 {"smoothed_voxels", active},
                 {"constraints", classes.constraints.size()},
                 {"frame_smoothness_initial", smoothed.initial_energy},
                 {"frame_smoothness_start", smoothed.start_energy},
                 {"frame_smoothness_final", smoothed.final_energy},
                 {"frame_smoothness_ratio", smoothed.final_energy / std::max(smoothed.initial_energy, 1e-300)},
                 {"smoothing_sweeps", smoothed.iterations},
                 {"constraint_angle_max_deg", smoothed.max_constraint_angle_rad * 180.0 / 3.14159265358979323846},
                 {"corner_candidates", corners.candidates.size()},
                 {"edge_points", corners.num_edge_points},
                 {"corners", param.corner_voxels.size()},
                 {"param_grid", {param.grid_nx, param.grid_ny, param.grid_nz}},
                 {"cg_iterations", param.cg_iterations},
                 {"cg_converged", param.converged},
                 {"inverted_cells", param.inverted_cells},
                 {"inverted_cells_unblended", param.inverted_cells_unblended},
                 {"min_jacobian", param.min_jacobian},
                 {"identity_blend", param.identity_blend},
                 {"alignment_rms_deg", param.alignment_rms_deg},
                 {"alignment_rms_deg_identity", param.alignment_rms_deg_identity},
                 {"alignment_rms_deg_reliable", param.alignment_rms_deg_reliable},
                 {"alignment_rms_deg_reliable_identity", param.alignment_rms_deg_reliable_identity},
                 {"volume_ratio_min", param.volume_ratio_min},
                 {"volume_ratio_max", param.volume_ratio_max}};
      if (fit_curve && run + 1 == runs) {
        Eigen::MatrixX3d uvw = param.uvw;
        Eigen::MatrixXd targets(static_cast<Eigen::Index>(volume.num_voxels()), 4);
        for (int z = 0; z < volume.nz; ++z)
          for (int y = 0; y < volume.ny; ++y)
            for (int x = 0; x < volume.nx; ++x) {
              const auto v = static_cast<Eigen::Index>(volume.index(x, y, z));
              if (identity_map)
                uvw.row(v) = Eigen::RowVector3d(x / (volume.nx - 1.0), y / (volume.ny - 1.0), z / (volume.nz - 1.0));
              targets.row(v) = Eigen::RowVector4d(x * volume.spacing.x(), y * volume.spacing.y(), z * volume.spacing.z(),
                                                  volume.samples[static_cast<std::size_t>(v)]);
            }
        volspline::spline::AdaptiveDensityOptions fit_options;
        fit_options.max_rms_rel = 0.001;
        fit_options.max_control_points = max_control_points;
        fit_options.min_gain_rate = 0.0;
        fit_options.initial_cells = initial_cells;
        const double f0 = cpu_now();
        const auto r = volspline::spline::fit_scattered_adaptive(uvw, targets, {volume.nx, volume.ny, volume.nz}, fit_options);
        json curve = json::array();
        for (const auto& level : r.levels) curve.push_back({level.control_points, 100.0 * level.rms_rel});
        quality["curve_cp_rms_percent"] = curve;
        quality["fit_cpu_s"] = cpu_now() - f0;
      }
    }
    json times;
    for (int s = 0; s < 7; ++s) times[stages[s]] = {{"wall_s", median(wall[s])}, {"cpu_s", median(cpu[s])}};
    const std::string name = path.substr(path.find_last_of('/') + 1);
    std::cout << json{{"volume", name}, {"runs", runs}, {"seconds", times}, {"quality", quality}}.dump() << std::endl;
  }
  return 0;
}
