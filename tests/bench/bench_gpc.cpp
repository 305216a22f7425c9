// SPDX-License-Identifier: MIT
// gpc whole-job time (read + job, one thread), median of N runs (wall and CPU: the machine may
// be shared), with the per-stage CPU times (medians; a stage runs from its progress report to
// the next) and, timed again (CPU) on the last run's cuboids, the parts of the volumetric map
// stage: the surface maps (§3.4.1, with their largest CG iteration count) and their inverse
// lookups (locator build and one lookup per boundary grid node), medians of N repetitions.
// --parts-only runs the job once without untangling or padding (to get the cuboids) and times
// only the parts. The default mesh is the shared kitten. The CLI tunes glibc's heap
// (cli/heap_tuning); for the same allocation costs run with
// GLIBC_TUNABLES=glibc.malloc.mmap_threshold=33554432:glibc.malloc.trim_threshold=1073741824.
// usage: bench_gpc [MESH] [--runs N] [--grid-nodes N] [--limbs P] [--parts-only]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "core/common/progress.h"
#include "core/io/mesh_io.h"
#include "core/param/cuboid_surface_locator.h"
#include "core/pipeline/gpc_job.h"
#include "tests/bench/stage_cpu_times.h"

int main(int argc, char** argv) {
  using namespace volspline;
  using Clock = std::chrono::steady_clock;
  using bench::median;
  std::string path = std::string(VOLSPLINE_SHARED_DATA) + "/meshes/kitten.off";
  pipeline::GpcOptions options;
  int runs = 5;
  bool parts_only = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc)
      runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--grid-nodes" && i + 1 < argc)
      options.grid.target_nodes = std::atoi(argv[++i]);
    else if (a == "--parts-only")
      parts_only = true;
    else if (a == "--limbs" && i + 1 < argc)
      options.limb_persistence = std::atof(argv[++i]);
    else
      path = a;
  }
  auto seconds_since = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  auto cpu_since = [](std::clock_t t0) { return double(std::clock() - t0) / CLOCKS_PER_SEC; };
  try {
    std::vector<double> seconds, cpu_seconds, read_seconds;
    bench::StageCpuTimes stage_cpu;
    pipeline::GpcResult result;
    if (parts_only) {
      options.grid.untangle = param::GpcGridOptions::Untangle::Off;
      options.grid.padding = param::GpcGridOptions::Padding::Off;
    }
    for (int run = 0; run < (parts_only ? 1 : runs); ++run) {
      const auto start = Clock::now();
      const std::clock_t cpu_start = std::clock();
      const mesh::TriangleMesh mesh = io::read_mesh(path);
      read_seconds.push_back(cpu_since(cpu_start));
      result = pipeline::run_gpc(mesh, path, options, stage_cpu.run_progress());
      seconds.push_back(seconds_since(start));
      cpu_seconds.push_back(cpu_since(cpu_start));
    }
    // The parts of the volumetric map, on the last run's cuboid surfaces.
    std::vector<double> surface_map_s, locator_s, lookup_s;
    int cg_iterations = 0, surface_faces = 0;
    param::CuboidSurfaceMapOptions map_options;
    map_options.area_balance_iterations = options.grid.area_balance_iterations;
    std::vector<mesh::HalfedgeMesh> meshes;
    for (const polycube::CuboidSurface& s : result.construction.surfaces) {
      meshes.push_back(mesh::HalfedgeMesh::build(s.mesh, "cuboid"));
      surface_faces += meshes.back().num_faces();
    }
    double sink = 0.0;
    for (int run = 0; run < runs; ++run) {
      double map_s = 0.0, build_s = 0.0, locate_s = 0.0;
      for (std::size_t c = 0; c < meshes.size(); ++c) {
        const mesh::HalfedgeMesh& hm = meshes[c];
        auto t0 = std::clock();
        const param::CuboidSurfaceMap map =
            param::compute_cuboid_surface_map(hm, result.construction.surfaces[c].layout, map_options);
        map_s += cpu_since(t0);
        cg_iterations = std::max(cg_iterations, map.cg_iterations);
        t0 = std::clock();
        const param::CuboidSurfaceLocator locator(hm, map);
        build_s += cpu_since(t0);
        const auto& n = result.map.grids[c].nodes;
        t0 = std::clock();
        for (int k = 0; k < n[2]; ++k)
          for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i) {
              if (i != 0 && j != 0 && k != 0 && i + 1 != n[0] && j + 1 != n[1] && k + 1 != n[2]) continue;
              sink += locator.locate_uvw(Eigen::Vector3d(double(i) / (n[0] - 1), double(j) / (n[1] - 1),
                                                         double(k) / (n[2] - 1)))
                          .sum();
            }
        locate_s += cpu_since(t0);
      }
      surface_map_s.push_back(map_s);
      locator_s.push_back(build_s);
      lookup_s.push_back(locate_s);
    }
    if (sink == 1e300) std::printf("%g", sink);  // keeps the lookups
    const pipeline::GpcStats& stats = result.stats;
    std::printf("{\n  \"bench\": \"gpc\",\n  \"mesh\": \"%s\",\n  \"runs\": %d,\n", path.c_str(), runs);
    std::printf("  \"median_s\": %.4f,\n  \"min_s\": %.4f,\n  \"max_s\": %.4f,\n  \"median_cpu_s\": %.4f,\n",
                median(seconds), *std::min_element(seconds.begin(), seconds.end()),
                *std::max_element(seconds.begin(), seconds.end()), median(cpu_seconds));
    std::printf("  \"cuboids\": %d,\n  \"surface_vertices\": %d,\n  \"cuboid_surface_faces\": %d,\n", stats.cuboids,
                stats.surface_vertices, surface_faces);
    std::printf("  \"flipped_triangles\": %d,\n  \"grid_inverted_hexes\": %d,\n  \"grid_min_scaled_jacobian\": %.6g,\n",
                stats.flipped_triangles, stats.grid_inverted_hexes, stats.grid_min_scaled_jacobian);
    std::printf("  \"stage_cpu_s\": {\"read\": %.4f", median(read_seconds));
    for (const std::string& stage : stage_cpu.stages())
      std::printf(", \"%s\": %.4f", stage.c_str(), stage_cpu.median_seconds(stage));
    std::printf("},\n  \"volumetric_map_parts_cpu_s\": {\"surface_maps\": %.4f, \"locators\": %.4f, "
                "\"lookups\": %.4f},\n",
                median(surface_map_s), median(locator_s), median(lookup_s));
    std::printf("  \"surface_map_cg_iterations\": %d\n}\n", cg_iterations);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_gpc: %s\n", e.what());
    return 1;
  }
  return 0;
}
