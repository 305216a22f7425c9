// SPDX-License-Identifier: MIT
// Folds of mesh2spline's spline off the lattice the job measures on: for each mesh and each of
// a few fixed rotations of it, the default job (one thread), then the scaled Jacobian at the
// N³ cell centres for N = 80, 96, 128 (the job's own sampled measure is every cell's Gauss
// points; 64³ is the untangler's polish lattice on bunny and bimba). The untangler's outcome at such points moves by a few points with
// any change of rounding, so one run says little; the sum over the ensemble compares versions.
// Prints JSON: per run the folded points per lattice, the untangling and job CPU seconds; totals.
// usage: bench_fold_ensemble [MESH ...] [--rotations K]   (default: bunny_closed and bimba, K = 3)
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "core/io/mesh_io.h"
#include "core/pipeline/mesh2spline_job.h"

using namespace volspline;

namespace {

// Rotation k of the ensemble: k = 0 is the identity, then fixed angles about skew axes.
Eigen::Matrix3d rotation(int k) {
  if (k == 0) return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 0.3 * k, -0.7 + 0.4 * k).normalized();
  return Eigen::AngleAxisd(0.45 * k, axis).toRotationMatrix();
}

// Cell centres of the n³ lattice with scaled Jacobian ≤ 0.
long folded(const spline::TSpline& s, int n) {
  std::array<std::vector<double>, 3> centres;
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < n; ++i)
      centres[a].push_back(s.domain_min()(a) + (s.domain_max()(a) - s.domain_min()(a)) * (i + 0.5) / n);
  long count = 0;
  s.evaluate_lattice_with_jacobian(centres, [&](int, int, int, const double*, const double* jacobian) {
    const Eigen::Map<const Eigen::Matrix3d> j(jacobian);
    const double scale = j.col(0).norm() * j.col(1).norm() * j.col(2).norm();
    count += !(scale > 0.0 && j.determinant() / scale > 0.0);
  });
  return count;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> paths;
  int rotations = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--rotations" && i + 1 < argc)
      rotations = std::max(1, std::atoi(argv[++i]));
    else
      paths.push_back(a);
  }
  if (paths.empty())
    paths = {std::string(VOLSPLINE_SHARED_DATA) + "/meshes/bunny_closed.obj",
             std::string(VOLSPLINE_SHARED_DATA) + "/meshes/bimba.off"};
  const std::array<int, 3> lattices = {80, 96, 128};
  try {
    std::array<long, 3> totals = {0, 0, 0};
    long negative_gauss = 0;
    double cpu_total = 0.0;
    std::printf("{\n  \"bench\": \"fold_ensemble\",\n  \"runs\": [\n");
    bool first = true;
    for (const std::string& path : paths) {
      const mesh::TriangleMesh input = io::read_mesh(path);
      for (int k = 0; k < rotations; ++k) {
        mesh::TriangleMesh mesh = input;
        const Eigen::Matrix3d r = rotation(k);
        for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v)
          mesh.positions.row(v) = (r * mesh.positions.row(v).transpose()).transpose();
        const std::clock_t start = std::clock();
        const pipeline::Mesh2SplineResult result = pipeline::run_mesh2spline(mesh, path, {});
        const double cpu = double(std::clock() - start) / CLOCKS_PER_SEC;
        cpu_total += cpu;
        double untangle = 0.0;
        for (const auto& [stage, seconds] : result.stats.times_s)
          if (stage == "untangle") untangle = seconds;
        const long n_gauss = std::lround(result.stats.negative_jacobian_fraction * double(result.stats.jacobian_samples));
        negative_gauss += n_gauss;
        std::printf("%s    {\"mesh\": \"%s\", \"rotation\": %d, \"folded_gauss\": %ld", first ? "" : ",\n", path.c_str(),
                    k, n_gauss);
        first = false;
        for (std::size_t q = 0; q < lattices.size(); ++q) {
          const long f = folded(result.spline, lattices[q]);
          totals[q] += f;
          std::printf(", \"folded_%d\": %ld", lattices[q], f);
        }
        std::printf(", \"untangle_s\": %.3f, \"cpu_s\": %.3f}", untangle, cpu);
      }
    }
    std::printf("\n  ],\n  \"folded_gauss\": %ld, \"folded_80\": %ld, \"folded_96\": %ld, \"folded_128\": %ld,",
                negative_gauss, totals[0], totals[1], totals[2]);
    std::printf(" \"cpu_s\": %.3f\n}\n", cpu_total);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_fold_ensemble: %s\n", e.what());
    return 1;
  }
  return 0;
}
