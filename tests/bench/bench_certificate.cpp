// SPDX-License-Identifier: MIT
// Bézier extraction and det J certificate of spline JSON files (one thread): time per cell
// (extraction alone, extraction + certificate; median of 5), the certificate's figures, and a
// brute-force check: on `--check-cells` random cells, `--samples` random points each (and the
// 8 corners), no det J below the cell's certified lower bound. Prints JSON.
//   bench_certificate SPLINE.json ... [--check-cells 20] [--samples 1000000] [--seed 1]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "core/io/spline_json.h"
#include "core/spline/bezier_extraction.h"
#include "core/spline/jacobian_certificate.h"

using namespace volspline::spline;

namespace {

constexpr int kRuns = 5;

double thread_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

template <class F>
double median_seconds(F&& run) {
  std::vector<double> t;
  for (int r = 0; r < kRuns; ++r) {
    const double start = thread_seconds();
    run();
    t.push_back(thread_seconds() - start);
  }
  std::sort(t.begin(), t.end());
  return t[kRuns / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  int check_cells = 20;
  long samples = 1000000;
  unsigned seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--check-cells" && i + 1 < argc) check_cells = std::atoi(argv[++i]);
    else if (a == "--samples" && i + 1 < argc) samples = std::atol(argv[++i]);
    else if (a == "--seed" && i + 1 < argc) seed = unsigned(std::atol(argv[++i]));
    else files.push_back(a);
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: bench_certificate SPLINE.json ... [--check-cells N] [--samples M] [--seed S]\n");
    return 2;
  }
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const std::string& file : files) {
    TSpline spline = volspline::io::read_spline_json(file);
    spline.use_cell_polynomials();
    const int cells = spline.num_cells();
    double sink = 0;
    const double extract_s = median_seconds([&] {
      for (int c = 0; c < cells; ++c) sink += extract_bezier_cell(spline, c).points[0];
    });
    JacobianCertificate certificate;
    const double certify_s = median_seconds([&] { certificate = certify_jacobian(spline); });
    int leaves = 0, subdivided = 0;
    for (int c = 0; c < cells; ++c) {
      const JacobianCellBound b = certify_bezier_cell(extract_bezier_cell(spline, c), {});
      leaves += b.leaves;
      subdivided += b.leaves > 1;
    }
    // Brute force: the smallest det J over random points of random cells against the bound.
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    nlohmann::ordered_json checks = nlohmann::ordered_json::array();
    int violations = 0;
    for (int n = 0; n < check_cells; ++n) {
      const int c = int(rng() % std::uint64_t(cells));
      const BezierCell cell = extract_bezier_cell(spline, c);
      const JacobianCellBound bound = certify_bezier_cell(cell, {});
      double lowest = 1e300;
      for (long s = 0; s < samples + 8; ++s) {
        Eigen::Vector3d p(unit(rng), unit(rng), unit(rng));
        if (s < 8) p = Eigen::Vector3d(s & 1, (s >> 1) & 1, (s >> 2) & 1);
        double value[3], jacobian[9];
        evaluate_bezier_cell(cell, p, value, jacobian);
        lowest = std::min(lowest, Eigen::Map<const Eigen::Matrix3d>(jacobian).determinant());
      }
      // Allowance: the certificate's τ and the samples' own rounding.
      const double slack = 1e-12 * std::abs(bound.det_j_lower_bound) + 1e-12;
      const bool ok = lowest >= bound.det_j_lower_bound - slack;
      violations += !ok;
      checks.push_back({{"cell", c},
                        {"status", bound.status == JacobianCellStatus::Certified ? "certified"
                                   : bound.status == JacobianCellStatus::Negative ? "negative"
                                                                                  : "undecided"},
                        {"det_j_lower_bound", bound.det_j_lower_bound},
                        {"sampled_min_det_j", lowest},
                        {"ok", ok}});
    }
    nlohmann::ordered_json r;
    r["file"] = file;
    r["cells"] = cells;
    r["control_points"] = spline.num_functions();
    r["extraction_us_per_cell"] = 1e6 * extract_s / cells;
    r["extraction_and_certificate_us_per_cell"] = 1e6 * certify_s / cells;
    r["certificate_s"] = certify_s;
    r["jacobian_certified_fraction"] = certificate.jacobian_certified_fraction;
    r["det_j_lower_bound_rel"] = certificate.det_j_lower_bound_rel;
    r["uncertified_cells"] = certificate.uncertified.size();
    // Uncertified cells by status and by how many domain faces they touch (0 interior, 1 face,
    // 2 cuboid edge, 3 corner).
    int by_status[3] = {0, 0, 0}, by_faces[4] = {0, 0, 0, 0};
    for (const UncertifiedCell& u : certificate.uncertified) {
      ++by_status[int(u.bound.status)];
      int faces = 0;
      for (int a = 0; a < 3; ++a)
        faces += (u.uvw_min[a] == spline.domain_min()[a]) || (u.uvw_max[a] == spline.domain_max()[a]);
      ++by_faces[faces];
    }
    r["uncertified_negative"] = by_status[int(JacobianCellStatus::Negative)];
    r["uncertified_undecided"] = by_status[int(JacobianCellStatus::Undecided)];
    r["uncertified_touching_0_1_2_3_faces"] = {by_faces[0], by_faces[1], by_faces[2], by_faces[3]};
    r["subdivided_cells"] = subdivided;
    r["leaves"] = leaves;
    r["brute_force_samples_per_cell"] = samples;
    r["brute_force_violations"] = violations;
    r["brute_force"] = checks;
    r["sink"] = sink != 0;
    out.push_back(r);
  }
  std::printf("%s\n", out.dump(2).c_str());
  return 0;
}
