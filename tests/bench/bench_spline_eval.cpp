// SPDX-License-Identifier: MIT
// Evaluation throughput of the trivariate spline kernels (one thread): tensor B-spline volume,
// T-spline semi-standard (Eq. 4.3: F = Σ w_i p_i B_i, no division) and rational (Eq. 4.1:
// F = Σ w_i p_i B_i / Σ w_i B_i, the denominator summed too, and the Jacobian by the quotient
// rule), both from the same per-cell power forms (the numerator's D components and, for the
// rational form, the denominator), value only and value + Jacobian, one point at a time and
// through the cell-sorted batch API; and a GPC-spline (§3.5) at random (cuboid, uvw): a block of
// 8 rotated cuboids glued C² and a twisted closed tube, 16 intervals per longest side, or the
// spline JSON given with --gpc FILE (e.g. mesh2spline's output for a genus > 0 solid), with its
// own patches called directly as the reference in the same run (the cost of the cuboid dispatch
// and the box check).
// Prints JSON: evaluations per second, median of 5 runs over the same random parameters.
// usage: bench_spline_eval [COUNT] [--gpc FILE.json]
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/io/gpc_spline_io.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/gpc_spline.h"
#include "core/spline/tspline.h"
#include "core/spline/tspline_refinement.h"
#include "tests/unit/spline/gpc_test_domains.h"

using namespace volspline::spline;

namespace {

constexpr int kRuns = 5;

// CPU time of this thread: the machine is shared, wall time would count other processes.
double thread_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double median_rate(const std::function<double()>& run, int count, double* checksum) {
  std::vector<double> rates;
  for (int r = 0; r < kRuns; ++r) {
    const double start = thread_seconds();
    *checksum += run();
    const double seconds = thread_seconds() - start;
    rates.push_back(count / seconds);
  }
  std::sort(rates.begin(), rates.end());
  return rates[kRuns / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int num_control = 16;
  int count = 1000000;
  std::string gpc_file;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--gpc" && i + 1 < argc)
      gpc_file = argv[++i];
    else
      count = std::atoi(argv[i]);
  }
  if (count < 1) {
    std::fprintf(stderr, "usage: bench_spline_eval [COUNT >= 1] [--gpc FILE.json]\n");
    return 2;
  }
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);

  // 16 control points per axis: 14 grid coordinates, jittered (non-uniform) interior.
  std::array<std::vector<double>, 3> knots;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> grid(num_control - 2);
    for (int i = 0; i < num_control - 2; ++i) grid[i] = (i + (i > 0 && i < num_control - 3 ? 0.3 * (unit(rng) - 0.5) : 0.0)) / (num_control - 3);
    knots[a] = boundary_restricted_knots(grid);
  }
  Eigen::MatrixXd points(num_control * num_control * num_control, 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i) points.row(i) << normal(rng), normal(rng), normal(rng);
  const BsplineVolume volume(knots, points);
  const TSpline tensor = from_bspline_volume(volume);

  // A genuine T-spline: extra knots inserted into a subset of the blending functions.
  std::vector<NewKnots> new_knots(tensor.num_functions());
  for (int i = 0; i < tensor.num_functions(); ++i) {
    const BlendingKnots& k = tensor.knots()[i];
    if (k[0][2] < 0.5) new_knots[i][0] = {0.5 * (k[0][1] + k[0][2])};
    if (k[1][2] > 0.3 && k[1][2] < 0.7) new_knots[i][1] = {0.5 * (k[1][2] + k[1][3])};
  }
  const TSpline refined = refine_blending_functions(tensor, new_knots);

  std::vector<Eigen::Vector3d> params(count);
  for (Eigen::Vector3d& p : params) p = Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
  // Reference in the same run: parameters inside one small box (a few cells), so the cell data
  // stays in L1 and the rate shows the arithmetic cost without cache misses.
  std::vector<Eigen::Vector3d> params_local(count);
  for (Eigen::Vector3d& p : params_local) p = Eigen::Vector3d(0.41, 0.41, 0.41) + 0.03 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
  Eigen::MatrixX3d params_matrix(count, 3);
  for (int i = 0; i < count; ++i) params_matrix.row(i) = params[i].transpose();

  double checksum = 0.0;
  nlohmann::json out;
  out["benchmark"] = "bench_spline_eval";
  out["parameters"] = count;
  out["runs"] = kRuns;
  out["statistic"] = "median evaluations per second of thread CPU time, one thread";
  out["control_points_per_axis"] = num_control;
  out["forms"]["semi_standard"] =
      "Eq. 4.3: F = sum w_i p_i B_i; per cell one tricubic power form with D components, no division";
  out["forms"]["rational"] =
      "Eq. 4.1: F = sum w_i p_i B_i / sum w_i B_i; per cell the numerator's D components and the "
      "denominator's power form, one division, the Jacobian by the quotient rule";
  out["forms"]["batch"] =
      "evaluate_batch / evaluate_batch_with_jacobian: rows grouped by knot cell (radix sort), four "
      "rows of a cell in the four AVX2 lanes; bits equal to the one-point calls";

  out["bspline_volume"]["value"] = median_rate([&] {
    double s = 0.0, v[3];
    for (const Eigen::Vector3d& p : params) { volume.evaluate_to(p, v); s += v[0]; }
    return s;
  }, count, &checksum);
  out["bspline_volume"]["value_jacobian"] = median_rate([&] {
    double s = 0.0, v[3], j[9];
    for (const Eigen::Vector3d& p : params) { volume.evaluate_with_jacobian(p, v, j); s += v[0] + j[4]; }
    return s;
  }, count, &checksum);

  auto bench_tspline = [&](const TSpline& spline, const char* name) {
    nlohmann::json& o = out[name];
    o["control_points"] = spline.num_functions();
    o["cell_polynomials"] = spline.has_cell_polynomials();
    o["cells"] = spline.num_cells();
    o["max_functions_per_cell"] = spline.max_functions_per_cell();
    for (const TSplineForm form : {TSplineForm::SemiStandard, TSplineForm::Rational}) {
      const char* form_name = form == TSplineForm::SemiStandard ? "semi_standard" : "rational";
      o[form_name]["value"] = median_rate([&] {
        double s = 0.0, v[3];
        for (const Eigen::Vector3d& p : params) { spline.evaluate_to(p, form, v); s += v[0]; }
        return s;
      }, count, &checksum);
      o[form_name]["value_in_cache_reference"] = median_rate([&] {
        double s = 0.0, v[3];
        for (const Eigen::Vector3d& p : params_local) { spline.evaluate_to(p, form, v); s += v[0]; }
        return s;
      }, count, &checksum);
      // The batch outputs are allocated once: a fresh 24 to 96 MB array per call costs its page
      // faults, more than the evaluation on some machines.
      Eigen::MatrixXd values, jacobians;
      o[form_name]["value_batch"] = median_rate([&] {
        spline.evaluate_batch(params_matrix, form, values);
        return values(count / 2, 0);
      }, count, &checksum);
      o[form_name]["value_jacobian"] = median_rate([&] {
        double s = 0.0, v[3], j[9];
        for (const Eigen::Vector3d& p : params) { spline.evaluate_with_jacobian(p, form, v, j); s += v[0] + j[4]; }
        return s;
      }, count, &checksum);
      o[form_name]["value_jacobian_batch"] = median_rate([&] {
        spline.evaluate_batch_with_jacobian(params_matrix, form, values, jacobians);
        return values(count / 2, 0) + jacobians(count / 2, 4);
      }, count, &checksum);
    }
    o["semi_standard_over_rational"]["value"] =
        o["semi_standard"]["value"].get<double>() / o["rational"]["value"].get<double>();
    o["semi_standard_over_rational"]["value_batch"] =
        o["semi_standard"]["value_batch"].get<double>() / o["rational"]["value_batch"].get<double>();
    o["semi_standard_over_rational"]["value_jacobian"] =
        o["semi_standard"]["value_jacobian"].get<double>() / o["rational"]["value_jacobian"].get<double>();
    o["semi_standard_over_rational"]["value_jacobian_batch"] =
        o["semi_standard"]["value_jacobian_batch"].get<double>() / o["rational"]["value_jacobian_batch"].get<double>();
  };
  bench_tspline(tensor, "tspline_tensor");
  bench_tspline(refined, "tspline_refined");
  out["tspline_tensor_over_bspline_volume"] =
      out["tspline_tensor"]["semi_standard"]["value"].get<double>() / out["bspline_volume"]["value"].get<double>();

  // GPC-splines: random cuboids (in proportion to their volume) and points inside them.
  auto bench_gpc = [&](const GpcSpline& spline, const std::string& name) {
    nlohmann::json& o = out["gpc_spline"][name];
    o["cuboids"] = spline.num_cuboids();
    o["control_points"] = spline.num_functions();
    o["continued_interfaces"] = spline.num_continued_interfaces();
    long cells = 0;
    double polynomial_bytes = 0.0;
    for (int c = 0; c < spline.num_cuboids(); ++c) {
      const TSpline& patch = spline.patch(c);
      cells += patch.num_cells();
      if (patch.has_cell_polynomials()) polynomial_bytes += double(patch.num_cells()) * 64 * (patch.dimension() + 1) * 8;
    }
    o["cells"] = cells;
    o["cell_polynomial_mib"] = polynomial_bytes / (1024.0 * 1024.0);
    std::vector<double> volume_share;
    for (int c = 0; c < spline.num_cuboids(); ++c) {
      const auto& size = spline.domain().cuboids[c].size;
      volume_share.push_back(size[0] * size[1] * size[2]);
    }
    std::discrete_distribution<int> pick(volume_share.begin(), volume_share.end());
    std::vector<int> cuboid(count);
    std::vector<Eigen::Vector3d> uvw(count);
    Eigen::MatrixX3d uvw_matrix(count, 3);
    for (int k = 0; k < count; ++k) {
      cuboid[k] = pick(rng);
      const auto& size = spline.domain().cuboids[cuboid[k]].size;
      uvw[k] = Eigen::Vector3d(unit(rng) * size[0], unit(rng) * size[1], unit(rng) * size[2]);
      uvw_matrix.row(k) = uvw[k].transpose();
    }
    Eigen::MatrixXd values, jacobians;
    o["value_batch"] = median_rate([&] {
      spline.evaluate_batch(cuboid, uvw_matrix, values);
      return values(count / 2, 0);
    }, count, &checksum);
    o["value_jacobian_batch"] = median_rate([&] {
      spline.evaluate_batch(cuboid, uvw_matrix, values, &jacobians);
      return values(count / 2, 0) + jacobians(count / 2, 4);
    }, count, &checksum);
    o["value_jacobian"] = median_rate([&] {
      double s = 0.0, v[4], j[12];
      for (int k = 0; k < count; ++k) { spline.evaluate_with_jacobian(cuboid[k], uvw[k], v, j); s += v[0] + j[4]; }
      return s;
    }, count, &checksum);
    o["patch_value_jacobian_reference"] = median_rate([&] {
      double s = 0.0, v[4], j[12];
      for (int k = 0; k < count; ++k) {
        spline.patch(cuboid[k]).evaluate_with_jacobian(uvw[k], TSplineForm::SemiStandard, v, j);
        s += v[0] + j[4];
      }
      return s;
    }, count, &checksum);
    o["value"] = median_rate([&] {
      double s = 0.0, v[4];
      for (int k = 0; k < count; ++k) { spline.evaluate_to(cuboid[k], uvw[k], v); s += v[0]; }
      return s;
    }, count, &checksum);
    o["patch_value_reference"] = median_rate([&] {
      double s = 0.0, v[4];
      for (int k = 0; k < count; ++k) { spline.patch(cuboid[k]).evaluate_to(uvw[k], TSplineForm::SemiStandard, v); s += v[0]; }
      return s;
    }, count, &checksum);
  };
  auto random_gpc = [&](const volspline::polycube::GpcDomain& domain) {
    double longest = 0.0;
    for (const auto& c : domain.cuboids) longest = std::max({longest, c.size[0], c.size[1], c.size[2]});
    GpcSplineOptions options;
    options.intervals = gpc_uniform_intervals(domain, longest / 16);
    GpcSpline spline(domain, options);
    Eigen::MatrixXd p(spline.num_functions(), 3);
    for (Eigen::Index i = 0; i < p.size(); ++i) p.data()[i] = normal(rng);
    spline.set_points(p);
    return spline;
  };
  using namespace volspline::test;
  bench_gpc(random_gpc(glue_boxes(block_boxes({{{1.0, 0.7}, {0.8, 1.2}, {0.5, 0.9}}}, 11))), "block_8_cuboids");
  bench_gpc(random_gpc(torus_domain(true)), "twisted_tube");
  if (!gpc_file.empty()) {
    std::ifstream in(gpc_file, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    if (!in) {
      std::fprintf(stderr, "bench_spline_eval: cannot read '%s'\n", gpc_file.c_str());
      return 2;
    }
    try {
      bench_gpc(volspline::io::parse_gpc_spline_json(text.str(), gpc_file), "file");
      out["gpc_spline"]["file"]["path"] = gpc_file;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 2;
    }
  }
  out["checksum"] = checksum;
  std::printf("%s\n", out.dump(2).c_str());
  return 0;
}
