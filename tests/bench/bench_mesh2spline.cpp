// SPDX-License-Identifier: MIT
// mesh2spline whole-job time (read + job, one thread), median of 5 runs (wall and CPU: the
// machine may be shared), on a closed genus-0
// mesh (default: bunny_closed), plus the measures of the last run and, as the reference
// measured in the same run, the uniform tensor B-spline reaching the same rms_rel.
// Per-stage CPU time (medians) from the progress reports: each stage runs from its report to the
// next, so "fit level N" holds the fit of level N and the refinement after it.
// usage: bench_mesh2spline [MESH] [--fit grid|meshless] [--no-untangle] [--runs N] [--no-compare]
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/io/mesh_io.h"
#include "core/pipeline/mesh2spline_job.h"
#include "tests/bench/stage_cpu_times.h"

int main(int argc, char** argv) {
  using namespace volspline;
  using bench::median;
  std::string path = std::string(VOLSPLINE_SHARED_DATA) + "/meshes/bunny_closed.obj";
  pipeline::Mesh2SplineOptions options;
  int runs = 5;
  bool compare = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--no-untangle")
      options.untangle = pipeline::Mesh2SplineOptions::Untangle::Off;
    else if (a == "--no-compare")
      compare = false;
    else if (a == "--runs" && i + 1 < argc)
      runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--fit" && i + 1 < argc)
      options.fit = std::string(argv[++i]) == "meshless" ? pipeline::Mesh2SplineFit::Meshless
                                                          : pipeline::Mesh2SplineFit::Grid;
    else
      path = a;
  }
  try {
    std::vector<double> seconds, cpu_seconds;
    pipeline::Mesh2SplineStats stats;
    bench::StageCpuTimes stage_cpu;
    for (int run = 0; run < runs; ++run) {
      const auto start = std::chrono::steady_clock::now();
      const std::clock_t cpu_start = std::clock();
      const Progress progress = stage_cpu.run_progress();
      const mesh::TriangleMesh mesh = io::read_mesh(path);
      const auto result = pipeline::run_mesh2spline(mesh, path, options, progress);
      seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      cpu_seconds.push_back(double(std::clock() - cpu_start) / CLOCKS_PER_SEC);
      stats = result.stats;
    }
    pipeline::Mesh2SplineStats compared_stats;
    if (compare) {
      pipeline::Mesh2SplineOptions reference = options;
      reference.compare_uniform = pipeline::Mesh2SplineOptions::CompareUniform::On;
      compared_stats = pipeline::run_mesh2spline(io::read_mesh(path), path, reference).stats;
    }
    std::printf("{\n  \"bench\": \"mesh2spline\",\n  \"mesh\": \"%s\",\n  \"fit\": \"%s\",\n", path.c_str(),
                options.fit == pipeline::Mesh2SplineFit::Grid ? "grid" : "meshless");
    std::printf("  \"median_s\": %.4f,\n  \"min_s\": %.4f,\n  \"max_s\": %.4f,\n  \"median_cpu_s\": %.4f,\n", median(seconds),
                *std::min_element(seconds.begin(), seconds.end()), *std::max_element(seconds.begin(), seconds.end()),
                median(cpu_seconds));
    std::printf("  \"rms_rel\": %.6g,\n  \"max_rel\": %.6g,\n  \"hausdorff_rel\": %.6g,\n  \"rms_geo_rel\": %.6g,\n",
                stats.rms_rel, stats.max_rel, stats.hausdorff_rel, stats.rms_geo_rel);
    std::printf("  \"control_points\": %d,\n  \"levels\": %d,\n  \"min_scaled_jacobian\": %.6g,\n", stats.control_points,
                stats.levels, stats.min_scaled_jacobian);
    std::printf("  \"negative_jacobian_fraction\": %.6g,\n  \"semi_standard_max_error\": %.3g,\n",
                stats.negative_jacobian_fraction, stats.semi_standard_max_error);
    std::printf("  \"uniform_control_points\": %d,\n  \"uniform_rms_rel\": %.6g,\n  \"stage_s\": {",
                compared_stats.uniform_control_points, compared_stats.uniform_rms_rel);
    for (std::size_t i = 0; i < stats.times_s.size(); ++i)
      std::printf("%s\"%s\": %.4f", i ? ", " : "", stats.times_s[i].first.c_str(), stats.times_s[i].second);
    std::printf("},\n  \"stage_cpu_s\": {");
    const std::vector<std::string>& stages = stage_cpu.stages();
    for (std::size_t i = 0; i < stages.size(); ++i)
      std::printf("%s\"%s\": %.4f", i ? ", " : "", stages[i].c_str(), stage_cpu.median_seconds(stages[i]));
    std::printf("}\n}\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_mesh2spline: %s\n", e.what());
    return 1;
  }
  return 0;
}
