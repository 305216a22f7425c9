// SPDX-License-Identifier: MIT
// Evaluation throughput of the trivariate spline kernels (one thread): tensor B-spline volume,
// T-spline semi-standard (Eq. 4.3) and rational (Eq. 4.1), value only and value + Jacobian.
// Prints JSON: evaluations per second, median of 5 runs over the same random parameters.
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <functional>
#include <random>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/spline/bspline_volume.h"
#include "core/spline/tspline.h"
#include "core/spline/tspline_refinement.h"

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
  const int count = argc > 1 ? std::atoi(argv[1]) : 1000000;
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
      o[form_name]["value_batch"] = median_rate([&] {
        return spline.evaluate_batch(params_matrix, form)(count / 2, 0);
      }, count, &checksum);
      o[form_name]["value_jacobian"] = median_rate([&] {
        double s = 0.0, v[3], j[9];
        for (const Eigen::Vector3d& p : params) { spline.evaluate_with_jacobian(p, form, v, j); s += v[0] + j[4]; }
        return s;
      }, count, &checksum);
    }
    o["semi_standard_over_rational"]["value"] =
        o["semi_standard"]["value"].get<double>() / o["rational"]["value"].get<double>();
    o["semi_standard_over_rational"]["value_batch"] =
        o["semi_standard"]["value_batch"].get<double>() / o["rational"]["value_batch"].get<double>();
    o["semi_standard_over_rational"]["value_jacobian"] =
        o["semi_standard"]["value_jacobian"].get<double>() / o["rational"]["value_jacobian"].get<double>();
  };
  bench_tspline(tensor, "tspline_tensor");
  bench_tspline(refined, "tspline_refined");
  out["tspline_tensor_over_bspline_volume"] =
      out["tspline_tensor"]["semi_standard"]["value"].get<double>() / out["bspline_volume"]["value"].get<double>();
  out["checksum"] = checksum;
  std::printf("%s\n", out.dump(2).c_str());
  return 0;
}
