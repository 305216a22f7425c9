// SPDX-License-Identifier: MIT
// vol2spline density fitting on volumes (default: every raw volume of the shared data set):
// the uniform least-squares cubic B-spline baseline (control points per axis 8..40) and the
// adaptive T-spline curve (one point per refinement level), density RMS relative to the range.
// usage: bench_vol2spline [VOLUME.raw ...] [--max-rms R] [--max-control-points N] [--initial-cells N]
//                         [--marking F] [--no-uniform]
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "core/io/volume_io.h"
#include "core/spline/density_fitting.h"

int main(int argc, char** argv) {
  using namespace volspline;
  std::vector<std::string> paths;
  spline::AdaptiveDensityOptions options;
  options.max_rms_rel = 0.001;
  options.max_control_points = 60000;
  options.min_gain_rate = 0.0;  // curves: refine until the target or the budget
  options.min_level_growth = 0.0;
  bool uniform = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--max-rms" && i + 1 < argc)
      options.max_rms_rel = std::stod(argv[++i]);
    else if (a == "--max-control-points" && i + 1 < argc)
      options.max_control_points = std::stoi(argv[++i]);
    else if (a == "--initial-cells" && i + 1 < argc)
      options.initial_cells = std::stoi(argv[++i]);
    else if (a == "--marking" && i + 1 < argc)
      options.marking_fraction = std::stod(argv[++i]);
    else if (a == "--no-uniform")
      uniform = false;
    else
      paths.push_back(a);
  }
  if (paths.empty())
    for (const char* name : {"bucky_32x32x32_uint8.raw", "fuel_64x64x64_uint8.raw", "neghip_64x64x64_uint8.raw",
                             "tooth_103x94x161_uint8.raw"})
      paths.push_back(std::string(VOLSPLINE_SHARED_DATA) + "/volumes/" + name);
  try {
    std::printf("[\n");
    for (std::size_t p = 0; p < paths.size(); ++p) {
      const volume::Volume vol = io::read_volume(paths[p]);
      spline::GridSamples samples;
      samples.dims = {vol.nx, vol.ny, vol.nz};
      samples.values.assign(vol.samples.begin(), vol.samples.end());
      std::printf("  {\"volume\": \"%s\",\n   \"uniform\": [", paths[p].c_str());
      if (uniform) {
        bool first = true;
        for (int n : {8, 12, 16, 24, 32, 40}) {
          if (n > vol.nx || n > vol.ny || n > vol.nz) continue;
          const auto start = std::chrono::steady_clock::now();
          const auto fit = spline::fit_uniform_bspline(samples, {n, n, n});
          const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          std::printf("%s\n     {\"per_axis\": %d, \"control_points\": %d, \"density_rms_rel\": %.6g, "
                      "\"density_max_rel\": %.6g, \"seconds\": %.3f}",
                      first ? "" : ",", n, n * n * n, fit.error.rms_rel, fit.error.max_rel, s);
          first = false;
        }
      }
      const auto start = std::chrono::steady_clock::now();
      const auto adaptive = spline::fit_density_adaptive(samples, options);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("],\n   \"adaptive_seconds\": %.3f,\n   \"adaptive\": [", s);
      for (std::size_t l = 0; l < adaptive.levels.size(); ++l)
        std::printf("%s\n     {\"level\": %zu, \"control_points\": %d, \"density_rms_rel\": %.6g, "
                    "\"density_max_rel\": %.6g, \"cg_iterations\": %d, \"leaves\": %d}",
                    l ? "," : "", l, adaptive.levels[l].control_points, adaptive.levels[l].rms_rel,
                    adaptive.levels[l].max_rel, adaptive.levels[l].cg_iterations, adaptive.levels[l].leaves);
      std::printf("]}%s\n", p + 1 < paths.size() ? "," : "");
      std::fflush(stdout);
    }
    std::printf("]\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_vol2spline: %s\n", e.what());
    return 1;
  }
  return 0;
}
