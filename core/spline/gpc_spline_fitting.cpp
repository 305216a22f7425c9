// SPDX-License-Identifier: MIT
#include "core/spline/gpc_spline_fitting.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "core/common/error.h"
#include "core/linalg/conjugate_gradient.h"
#include "core/spline/grouped_gram.h"

namespace volspline::spline {

namespace {

// Shapes and values of `samples` against `spline` (cuboid ids are checked where they are used).
void check_samples(const GpcSpline& spline, const GpcSamples& samples, const std::string& who) {
  const Eigen::Index m = samples.uvw.rows();
  const int dim = spline.dimension();
  if (static_cast<Eigen::Index>(samples.cuboid.size()) != m || samples.values.rows() != m ||
      samples.values.cols() != dim)
    throw Error(who + ": samples have " + std::to_string(samples.cuboid.size()) + " cuboid ids, " +
                std::to_string(m) + " uvw rows and " + std::to_string(samples.values.rows()) + "x" +
                std::to_string(samples.values.cols()) + " values (expected m, m and m x " + std::to_string(dim) + ")");
  if (!samples.values.allFinite()) throw Error(who + ": a sample value is not finite");
  if (!samples.weight.empty() && static_cast<Eigen::Index>(samples.weight.size()) != m)
    throw Error(who + ": " + std::to_string(samples.weight.size()) + " weights for " + std::to_string(m) +
                " samples");
  for (double w : samples.weight)
    if (!(w > 0.0) || !std::isfinite(w)) throw Error(who + ": a sample weight is not finite and positive");
}

}  // namespace

GpcSplineFitReport fit_gpc_spline(GpcSpline& spline, const GpcSamples& samples, const GpcSplineFitOptions& options) {
  const Eigen::Index m = samples.uvw.rows();
  const int dim = spline.dimension(), n = spline.num_functions();
  check_samples(spline, samples, "fit_gpc_spline");
  if (!(options.regularization >= 0.0) || !std::isfinite(options.regularization))
    throw Error("fit_gpc_spline: regularization must be finite and >= 0");
  if (!(options.tolerance >= 0.0)) throw Error("fit_gpc_spline: tolerance must be >= 0");
  if (options.max_iterations < 1) throw Error("fit_gpc_spline: max_iterations must be >= 1");
  // Eq. 3.5 rows grouped by (cuboid, knot cell): one dense Gram update per cell.
  std::vector<std::pair<std::int64_t, int>> order(static_cast<std::size_t>(m));
  for (Eigen::Index s = 0; s < m; ++s) {
    const int c = samples.cuboid[s];
    if (c < 0 || c >= spline.num_cuboids())
      throw Error("fit_gpc_spline: sample " + std::to_string(s) + " names cuboid " + std::to_string(c) + " of " +
                  std::to_string(spline.num_cuboids()));
    const std::int64_t cell = spline.cell_of(c, samples.uvw.row(s).transpose());
    order[s] = {(static_cast<std::int64_t>(c) << 32) + cell, static_cast<int>(s)};
  }
  std::sort(order.begin(), order.end());
  std::vector<int> group_begin, group_offsets{0}, group_cols, row_counts;
  std::vector<int> ids;
  std::vector<double> values;
  for (std::size_t b = 0; b < order.size();) {
    std::size_t e = b;
    while (e < order.size() && order[e].first == order[b].first) ++e;
    const int s = order[b].second;
    spline.basis_at(samples.cuboid[s], samples.uvw.row(s).transpose(), {0, 0, 0}, ids, values);
    group_cols.insert(group_cols.end(), ids.begin(), ids.end());
    group_offsets.push_back(static_cast<int>(group_cols.size()));
    group_begin.push_back(static_cast<int>(b));
    row_counts.push_back(static_cast<int>(e - b));
    b = e;
  }
  GroupedGram gram(n, dim, std::move(group_offsets), std::move(group_cols));
  gram.add_all(row_counts, [&](int g, Eigen::MatrixXd& block, Eigen::MatrixXd& rhs) {
    thread_local std::vector<int> row_ids;  // scratch: the callback may run on several threads
    thread_local std::vector<double> row_values;
    const int count = row_counts[g], k = gram.group_size(g);
    block.resize(count, k);
    rhs.resize(count, dim);
    for (int r = 0; r < count; ++r) {
      const int s = order[static_cast<std::size_t>(group_begin[g] + r)].second;
      spline.basis_at(samples.cuboid[s], samples.uvw.row(s).transpose(), {0, 0, 0}, row_ids, row_values);
      // Every point of one cell has the cell's list (TSpline::cell_functions), so the same ids.
      const double root = samples.weight.empty() ? 1.0 : std::sqrt(samples.weight[s]);
      for (int c = 0; c < k; ++c) block(r, c) = root * row_values[c];
      rhs.row(r) = root * samples.values.row(s);
    }
  });
  Eigen::MatrixXd atb = gram.rhs();
  linalg::CsrMatrix ata = gram.take_symmetric();

  GpcSplineFitReport report;
  report.samples = static_cast<int>(m);
  report.unknowns = n;
  const std::vector<int>& off = ata.row_offsets();
  const std::vector<int>& col = ata.col_indices();
  std::vector<double>& val = ata.values();
  std::vector<int> diagonal(static_cast<std::size_t>(n), -1);
  double trace = 0.0;
  int sampled = 0;
  for (int r = 0; r < n; ++r)
    for (int q = off[r]; q < off[r + 1]; ++q)
      if (col[q] == r) {
        diagonal[r] = q;
        trace += val[q];
        sampled += val[q] > 0.0;
      }
  const double eps2 = options.regularization * (sampled > 0 ? trace / sampled : 1.0);
  const Eigen::MatrixXd& current = spline.points();
  for (int r = 0; r < n; ++r) {
    double& d = val[diagonal[r]];
    if (d > 0.0) {
      d += eps2;
      atb.row(r) += eps2 * current.row(r);
    } else {
      // No sample reaches function r: its row and column are empty, so fix its control point.
      d = 1.0;
      atb.row(r) = current.row(r);
      ++report.unsampled_functions;
    }
  }
  linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
  cg.set_tolerance(options.tolerance);
  cg.set_max_iterations(options.max_iterations);
  cg.compute(ata);
  Eigen::MatrixXd x = cg.solve(atb, current);
  report.converged = cg.info() == linalg::SolverInfo::Success;
  report.cg_iterations = cg.iterations();
  report.cg_residual = cg.residual();
  spline.set_points(std::move(x));

  double sum = 0.0;
  for (Eigen::Index s = 0; s < m; ++s) {
    const double err = (spline.evaluate(samples.cuboid[s], samples.uvw.row(s).transpose()) -
                        samples.values.row(s).transpose()).norm();
    sum += err * err;
    report.max_error = std::max(report.max_error, err);
  }
  report.rms_error = m > 0 ? std::sqrt(sum / static_cast<double>(m)) : 0.0;
  return report;
}

std::vector<std::array<std::vector<double>, 3>> gpc_refined_knot_lines(const GpcSpline& spline,
                                                                       const GpcSamples& samples, double growth,
                                                                       const std::vector<std::array<double, 3>>& min_interval,
                                                                       const std::vector<int>& first) {
  check_samples(spline, samples, "gpc_refined_knot_lines");
  if (!(growth > 1.0) || !std::isfinite(growth)) throw Error("gpc_refined_knot_lines: growth must be > 1");
  const int nc = spline.num_cuboids(), dim = spline.dimension();
  if (!min_interval.empty() && static_cast<int>(min_interval.size()) != nc)
    throw Error("gpc_refined_knot_lines: min_interval has " + std::to_string(min_interval.size()) + " entries for " +
                std::to_string(nc) + " cuboids");
  std::vector<std::array<std::vector<double>, 3>> lines(static_cast<std::size_t>(nc));
  std::vector<std::array<std::vector<double>, 3>> error(static_cast<std::size_t>(nc));
  for (int c = 0; c < nc; ++c)
    for (int a = 0; a < 3; ++a) {
      lines[c][a] = spline.knot_lines(c, a);
      error[c][a].assign(lines[c][a].size() - 1, 0.0);
    }
  for (int c : samples.cuboid)
    if (c < 0 || c >= nc)
      throw Error("gpc_refined_knot_lines: a sample names cuboid " + std::to_string(c) + " of " + std::to_string(nc));
  // The misfit goes to the three axes in proportion to (h_a³ ‖∂³F/∂u_a³‖)², the size of F's cubic
  // part over the sample's interval along a: an axis F is (nearly) quadratic along at this
  // resolution gains little from more knots (de Boor's knot placement measure, per axis).
  std::array<std::size_t, 3> interval{};
  std::array<double, 3> share{};
  auto shares = [&](Eigen::Index s) {
    const int c = samples.cuboid[s];
    const Eigen::Vector3d uvw = samples.uvw.row(s).transpose();
    double total = 0.0;
    for (int a = 0; a < 3; ++a) {
      const std::vector<double>& l = lines[c][a];
      interval[a] = static_cast<std::size_t>(std::upper_bound(l.begin() + 1, l.end() - 1, uvw(a)) - l.begin() - 1);
      const double h = l[interval[a] + 1] - l[interval[a]];
      std::array<int, 3> order{0, 0, 0};
      order[a] = 3;
      share[a] = std::pow(h, 6) * spline.derivative(c, uvw, order).squaredNorm();
      total += share[a];
    }
    for (int a = 0; a < 3; ++a) share[a] = total > 0.0 ? share[a] / total : 1.0 / 3.0;
  };
  std::vector<double> value(static_cast<std::size_t>(dim)), jacobian(static_cast<std::size_t>(3 * dim));
  for (Eigen::Index s = 0; s < samples.uvw.rows(); ++s) {
    const int c = samples.cuboid[s];
    spline.evaluate_with_jacobian(c, samples.uvw.row(s).transpose(), value.data(), jacobian.data());
    double r2 = 0.0;
    for (int d = 0; d < dim; ++d) r2 += (value[d] - samples.values(s, d)) * (value[d] - samples.values(s, d));
    if (!samples.weight.empty()) r2 *= samples.weight[s];
    shares(s);
    for (int a = 0; a < 3; ++a) error[c][a][interval[a]] += r2 * share[a];
  }
  struct Candidate {
    double error;
    int cuboid, axis, interval;
  };
  std::vector<Candidate> candidates;
  auto splittable = [&](int c, int a, int i) {
    const double shortest = min_interval.empty() ? 0.0 : min_interval[c][a];
    return lines[c][a][i + 1] - lines[c][a][i] > 2.0 * shortest;
  };
  for (int s : first) {
    if (s < 0 || s >= samples.uvw.rows())
      throw Error("gpc_refined_knot_lines: `first` names sample " + std::to_string(s) + " of " +
                  std::to_string(samples.uvw.rows()));
    shares(s);
    const int a = static_cast<int>(std::max_element(share.begin(), share.end()) - share.begin());
    const int c = samples.cuboid[s], i = static_cast<int>(interval[a]);
    if (splittable(c, a, i)) candidates.push_back({0.0, c, a, i});
  }
  const std::size_t firsts = candidates.size();
  for (int c = 0; c < nc; ++c)
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i + 1 < static_cast<int>(lines[c][a].size()); ++i) {
        if (!(error[c][a][i] > 0.0) || !splittable(c, a, i)) continue;
        // Per function it would add: a line along a adds about one function per column across a.
        double across = 1.0;
        for (int b = 0; b < 3; ++b)
          if (b != a) across *= static_cast<double>(lines[c][b].size() + 2);
        candidates.push_back({error[c][a][i] / across, c, a, i});
      }
  std::stable_sort(candidates.begin() + static_cast<std::ptrdiff_t>(firsts), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.error > y.error; });
  auto estimate = [&]() {
    double n = 0.0;
    for (int c = 0; c < nc; ++c)
      n += static_cast<double>(lines[c][0].size() + 2) * (lines[c][1].size() + 2) * (lines[c][2].size() + 2);
    return n;
  };
  const double target = growth * estimate();
  const auto old = lines;  // midpoints of the intervals as they were
  for (const Candidate& k : candidates) {
    if (estimate() >= target) break;
    const std::vector<double>& l = old[k.cuboid][k.axis];
    gpc_insert_knot_line(spline.domain(), lines, k.cuboid, k.axis, 0.5 * (l[k.interval] + l[k.interval + 1]));
  }
  return lines;
}

std::vector<int> gpc_marked_functions(const GpcSpline& spline, const GpcSamples& samples, double fraction,
                                      int max_count, int max_level, const std::vector<int>& first) {
  check_samples(spline, samples, "gpc_marked_functions");
  if (!(fraction > 0.0 && fraction <= 1.0)) throw Error("gpc_marked_functions: fraction must be in (0, 1]");
  if (max_count < 1) throw Error("gpc_marked_functions: max_count must be >= 1");
  const int n = spline.num_functions(), dim = spline.dimension();
  std::vector<double> share(static_cast<std::size_t>(n), 0.0);
  std::vector<int> ids;
  std::vector<double> values;
  for (Eigen::Index s = 0; s < samples.uvw.rows(); ++s) {
    const int c = samples.cuboid[s];
    if (c < 0 || c >= spline.num_cuboids())
      throw Error("gpc_marked_functions: sample " + std::to_string(s) + " names cuboid " + std::to_string(c));
    spline.basis_at(c, samples.uvw.row(s).transpose(), {0, 0, 0}, ids, values);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(dim);
    for (std::size_t k = 0; k < ids.size(); ++k) f += values[k] * spline.points().row(ids[k]).transpose();
    const double e = (samples.weight.empty() ? 1.0 : samples.weight[s]) * (f - samples.values.row(s).transpose()).squaredNorm();
    for (std::size_t k = 0; k < ids.size(); ++k) share[ids[k]] += values[k] * e;
  }
  std::vector<int> order;
  double total = 0.0;
  for (int i = 0; i < n; ++i) {
    total += share[i];
    if (spline.function_level(i) < max_level && share[i] > 0.0) order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return share[a] > share[b]; });
  std::vector<int> out;
  std::vector<char> taken_flag(static_cast<std::size_t>(n), 0);
  double taken = 0.0;
  auto take = [&](int i) {
    out.push_back(i);
    taken_flag[i] = 1;
    taken += share[i];
  };
  for (int s : first) {
    if (s < 0 || s >= samples.uvw.rows()) throw Error("gpc_marked_functions: first names sample " + std::to_string(s));
    spline.basis_at(samples.cuboid[s], samples.uvw.row(s).transpose(), {0, 0, 0}, ids, values);
    double largest = 0.0;
    for (std::size_t k = 0; k < ids.size(); ++k)
      if (spline.function_level(ids[k]) < max_level) largest = std::max(largest, values[k]);
    for (std::size_t k = 0; k < ids.size() && static_cast<int>(out.size()) < max_count; ++k)
      if (largest > 0.0 && values[k] >= 0.5 * largest && !taken_flag[ids[k]] && spline.function_level(ids[k]) < max_level)
        take(ids[k]);
  }
  for (int i : order) {
    if (taken >= fraction * total || static_cast<int>(out.size()) >= max_count) break;
    if (!taken_flag[i]) take(i);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace volspline::spline
