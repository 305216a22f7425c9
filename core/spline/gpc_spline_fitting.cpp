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

GpcSplineFitReport fit_gpc_spline(GpcSpline& spline, const GpcSamples& samples, const GpcSplineFitOptions& options) {
  const Eigen::Index m = samples.uvw.rows();
  const int dim = spline.dimension(), n = spline.num_functions();
  if (static_cast<Eigen::Index>(samples.cuboid.size()) != m || samples.values.rows() != m ||
      samples.values.cols() != dim)
    throw Error("fit_gpc_spline: samples have " + std::to_string(samples.cuboid.size()) + " cuboid ids, " +
                std::to_string(m) + " uvw rows and " + std::to_string(samples.values.rows()) + "x" +
                std::to_string(samples.values.cols()) + " values (expected m, m and m x " + std::to_string(dim) + ")");
  if (!(options.regularization >= 0.0) || !std::isfinite(options.regularization))
    throw Error("fit_gpc_spline: regularization must be finite and >= 0");
  if (!(options.tolerance >= 0.0)) throw Error("fit_gpc_spline: tolerance must be >= 0");
  if (options.max_iterations < 1) throw Error("fit_gpc_spline: max_iterations must be >= 1");
  if (!samples.values.allFinite()) throw Error("fit_gpc_spline: a sample value is not finite");
  if (!samples.weight.empty() && static_cast<Eigen::Index>(samples.weight.size()) != m)
    throw Error("fit_gpc_spline: " + std::to_string(samples.weight.size()) + " weights for " + std::to_string(m) +
                " samples");
  for (double w : samples.weight)
    if (!(w > 0.0) || !std::isfinite(w)) throw Error("fit_gpc_spline: a sample weight is not finite and positive");

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

}  // namespace volspline::spline
