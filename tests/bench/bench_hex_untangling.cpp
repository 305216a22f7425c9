// SPDX-License-Identifier: MIT
// The hex untangler alone on a synthetic fold: an n³ grid of unit cubes whose interior nodes are
// pushed by a seeded random field strong enough to fold cells, untangled with the boundary held
// (untangle_hex_mesh, as the GPC padded mesh's held pass), then improve_hex_mesh on all nodes.
// CPU seconds per run (min and median of N: the machine may be shared) and a checksum of the
// node positions, so that two builds can be compared for speed and for the same bits.
// usage: bench_hex_untangling [--n N] [--runs R] [--amplitude A]
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "core/param/hex_grid_untangling.h"

int main(int argc, char** argv) {
  using namespace volspline;
  int n = 24, runs = 3;
  double amplitude = 0.9;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--n") n = std::max(3, std::atoi(argv[i + 1]));
    if (a == "--runs") runs = std::max(1, std::atoi(argv[i + 1]));
    if (a == "--amplitude") amplitude = std::atof(argv[i + 1]);
  }
  auto id = [&](int i, int j, int k) { return i + n * (j + n * k); };
  mesh::Positions start(n * n * n, 3);
  std::vector<char> fixed(n * n * n, 0);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const bool boundary = i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1;
        fixed[id(i, j, k)] = boundary;
        start.row(id(i, j, k)) << i, j, k;
        // Folds in a few blobs: the displacement is strong only where all three coordinates are
        // near a multiple of 8.
        const double w = boundary ? 0.0 : ((i % 8 < 3 && j % 8 < 3 && k % 8 < 3) ? amplitude : 0.1);
        for (int d = 0; d < 3; ++d) start(id(i, j, k), d) += w * u(rng);
      }
  std::vector<std::array<int, 8>> hexes;
  for (int k = 0; k + 1 < n; ++k)
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        std::array<int, 8> h;
        for (int q = 0; q < 8; ++q) h[q] = id(i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1));
        hexes.push_back(h);
      }
  std::vector<double> seconds;
  param::HexGridUntangleReport report;
  int improved = 0;
  mesh::Positions xyz;
  for (int r = 0; r < runs; ++r) {
    xyz = start;
    const std::clock_t t0 = std::clock();
    report = param::untangle_hex_mesh(hexes, fixed, xyz);
    improved = param::improve_hex_mesh(hexes, fixed, xyz, 100);
    seconds.push_back(double(std::clock() - t0) / CLOCKS_PER_SEC);
  }
  std::uint64_t checksum = 1469598103934665603ull;  // FNV-1a over the position bytes
  for (Eigen::Index v = 0; v < xyz.rows(); ++v)
    for (int d = 0; d < 3; ++d) {
      const double x = xyz(v, d);
      unsigned char bytes[sizeof x];
      std::memcpy(bytes, &x, sizeof x);
      for (unsigned char b : bytes) checksum = (checksum ^ b) * 1099511628211ull;
    }
  std::vector<double> sorted = seconds;
  std::sort(sorted.begin(), sorted.end());
  std::printf("{\n  \"bench\": \"hex_untangling\",\n  \"n\": %d,\n  \"runs\": %d,\n", n, runs);
  std::printf("  \"initial_inverted\": %d,\n  \"final_inverted\": %d,\n  \"free_nodes\": %d,\n", report.initial_inverted,
              report.final_inverted, report.free_nodes);
  std::printf("  \"iterations\": %d,\n  \"improve_iterations\": %d,\n", report.iterations, improved);
  std::printf("  \"min_cpu_s\": %.4f,\n  \"median_cpu_s\": %.4f,\n  \"checksum\": \"%016llx\"\n}\n", sorted.front(),
              sorted[sorted.size() / 2], static_cast<unsigned long long>(checksum));
  return 0;
}
