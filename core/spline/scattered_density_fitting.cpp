// SPDX-License-Identifier: MIT
#include "core/spline/scattered_density_fitting.h"

#include <algorithm>
#include <utility>
#include <cassert>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/spline/component_solve.h"
#include "core/spline/bspline_volume.h"

namespace volspline::spline {

namespace {

std::vector<double> clamped_uniform(int intervals) {
  std::vector<double> k = {0.0, 0.0, 0.0};
  for (int i = 0; i <= intervals; ++i) k.push_back(i == intervals ? 1.0 : static_cast<double>(i) / intervals);
  for (int i = 0; i < 3; ++i) k.push_back(1.0);
  return k;
}

// Sum of squared density errors per leaf and the per-sample density of the spline (column 0).
std::vector<double> evaluate_column0(const TSpline& spline, const Eigen::MatrixX3d& uvw) {
  std::vector<double> out(static_cast<std::size_t>(uvw.rows()));
  double value[4];
  for (Eigen::Index s = 0; s < uvw.rows(); ++s) {
    spline.evaluate_to(uvw.row(s).transpose(), TSplineForm::SemiStandard, value);
    out[static_cast<std::size_t>(s)] = value[0];
  }
  return out;
}

// Replaces a spline by a one-function placeholder, freeing its evaluation grid before the next
// spline's is built (TSpline has no empty state).
void release(TSpline& spline) {
  spline = TSpline(std::vector<BlendingKnots>(1, spline.knots()[0]), Eigen::VectorXd::Ones(1),
                   Eigen::MatrixXd::Zero(1, spline.dimension()), TSplineAcceleration::FunctionLists);
}

}  // namespace

ScatteredFitReport fit_tspline_scattered(TSpline& spline, const RefinementGrid& cells, const Eigen::MatrixX3d& uvw,
                                         const Eigen::MatrixXd& targets, const std::vector<int>& components,
                                         const GridFitOptions& options) {
  assert(targets.rows() == uvw.rows() && targets.cols() == static_cast<Eigen::Index>(components.size()));
  const int n = spline.num_functions();
  const int k = static_cast<int>(components.size());
  const Eigen::Index m = uvw.rows();
  // Samples grouped by leaf (counting sort, stable: deterministic).
  std::vector<int> leaf(static_cast<std::size_t>(m));
  int max_id = 0;
  for (Eigen::Index s = 0; s < m; ++s) {
    leaf[s] = cells.leaf_of(uvw.row(s).transpose());
    max_id = std::max(max_id, leaf[s]);
  }
  std::vector<int> start(static_cast<std::size_t>(max_id) + 2, 0);
  for (int l : leaf) ++start[l + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<int> order(static_cast<std::size_t>(m));
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (Eigen::Index s = 0; s < m; ++s) order[fill[leaf[s]]++] = static_cast<int>(s);
  }
  // Pass 1: per non-empty leaf, the sorted blending functions non-zero at its samples.
  std::vector<int> group_begin, group_ids_offset(1, 0), group_ids;
  std::vector<int> stamp(n, -1);
  std::vector<int> ids;
  std::vector<double> values;
  for (int l = 0; l <= max_id; ++l) {
    if (start[l] == start[l + 1]) continue;
    const std::size_t first = group_ids.size();
    for (int p = start[l]; p < start[l + 1]; ++p) {
      spline.basis_at(uvw.row(order[p]).transpose(), {0, 0, 0}, ids, values);
      for (int id : ids)
        if (stamp[id] != l) {
          stamp[id] = l;
          group_ids.push_back(id);
        }
    }
    std::sort(group_ids.begin() + static_cast<std::ptrdiff_t>(first), group_ids.end());
    group_begin.push_back(l);
    group_ids_offset.push_back(static_cast<int>(group_ids.size()));
  }
  const int groups = static_cast<int>(group_begin.size());
  // Pattern: row i couples with every function of every leaf group holding i.
  std::vector<int> groups_of_offset(n + 1, 0), groups_of;
  for (int g = 0; g < groups; ++g)
    for (int q = group_ids_offset[g]; q < group_ids_offset[g + 1]; ++q) ++groups_of_offset[group_ids[q] + 1];
  for (int i = 0; i < n; ++i) groups_of_offset[i + 1] += groups_of_offset[i];
  groups_of.resize(groups_of_offset[n]);
  {
    std::vector<int> fill(groups_of_offset.begin(), groups_of_offset.end() - 1);
    for (int g = 0; g < groups; ++g)
      for (int q = group_ids_offset[g]; q < group_ids_offset[g + 1]; ++q) groups_of[fill[group_ids[q]]++] = g;
  }
  // Upper triangle only (j ≥ i; the diagonal first in every row): all that CG and its
  // preconditioner read, at half the memory and half the merge work.
  std::vector<int> offsets(1, 0), cols;
  std::fill(stamp.begin(), stamp.end(), -1);
  for (int i = 0; i < n; ++i) {
    const std::size_t first = cols.size();
    cols.push_back(i);
    stamp[i] = i;
    for (int q = groups_of_offset[i]; q < groups_of_offset[i + 1]; ++q) {
      const int g = groups_of[q];
      for (int r = group_ids_offset[g]; r < group_ids_offset[g + 1]; ++r)
        if (group_ids[r] > i && stamp[group_ids[r]] != i) {
          stamp[group_ids[r]] = i;
          cols.push_back(group_ids[r]);
        }
    }
    std::sort(cols.begin() + static_cast<std::ptrdiff_t>(first) + 1, cols.end());
    offsets.push_back(static_cast<int>(cols.size()));
  }
  cols.shrink_to_fit();
  std::vector<double> gram(cols.size(), 0.0);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, k);
  // Pass 2: per leaf group the lower triangle of the dense Gram block MᵀM (a symmetric rank
  // update: half the products of a full MᵀM), merged into the sorted upper rows.
  std::vector<int> local(n, -1);
  Eigen::MatrixXd block, t, local_gram;
  for (int g = 0; g < groups; ++g) {
    const int l = group_begin[g];
    const int f = group_ids_offset[g + 1] - group_ids_offset[g];
    const int* gid = group_ids.data() + group_ids_offset[g];
    for (int a = 0; a < f; ++a) local[gid[a]] = a;
    const int rows = start[l + 1] - start[l];
    block.setZero(rows, f);
    t.resize(rows, k);
    for (int r = 0; r < rows; ++r) {
      const int s = order[start[l] + r];
      spline.basis_at(uvw.row(s).transpose(), {0, 0, 0}, ids, values);
      for (std::size_t q = 0; q < ids.size(); ++q) block(r, local[ids[q]]) = spline.weights()(ids[q]) * values[q];
      t.row(r) = targets.row(s);
    }
    local_gram.setZero(f, f);
    local_gram.selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
    const Eigen::MatrixXd local_rhs = block.transpose() * t;
    for (int a = 0; a < f; ++a) {
      const int i = gid[a];
      rhs.row(i) += local_rhs.row(a);
      int p = offsets[i];
      for (int b = a; b < f; ++b) {
        while (cols[p] < gid[b]) ++p;
        gram[p] += local_gram(b, a);
      }
    }
  }
  double trace = 0.0;
  for (int i = 0; i < n; ++i) trace += gram[offsets[i]];
  const double mean = trace > 0.0 ? trace / n : 1.0;
  Eigen::MatrixXd x0(n, k);
  for (int c = 0; c < k; ++c) x0.col(c) = spline.points().col(components[c]);
  for (int i = 0; i < n; ++i) {
    double& d = gram[offsets[i]];
    const double ridge = options.regularization * (d > 0.0 ? d : mean);
    d += ridge;
    rhs.row(i) += ridge * x0.row(i);
  }
  linalg::CsrMatrix a = linalg::CsrMatrix::from_arrays(n, n, std::move(offsets), std::move(cols), std::move(gram));
  ScatteredFitReport report;
  report.unknowns = n;
  report.normal_nonzeros = 2LL * a.nnz() - n;  // both triangles
  const ComponentSolveReport solve =
      solve_components(spline, std::move(a), rhs, components, options.tolerance, options.max_iterations);
  report.cg_iterations = solve.cg_iterations;
  report.converged = solve.converged;
  return report;
}

ScatteredDensityResult fit_scattered_adaptive(const Eigen::MatrixX3d& uvw, const Eigen::MatrixXd& targets,
                                              const std::array<int, 3>& dims, const AdaptiveDensityOptions& options,
                                              const pipeline::Progress& progress) {
  if (targets.rows() != uvw.rows() || targets.cols() != 4)
    throw Error("scattered density fit: targets must be " + std::to_string(uvw.rows()) + "x4");
  if (uvw.rows() == 0) throw Error("scattered density fit: no samples");
  for (Eigen::Index s = 0; s < uvw.rows(); ++s)
    for (int a = 0; a < 3; ++a)
      if (!(uvw(s, a) >= 0.0 && uvw(s, a) <= 1.0))
        throw Error("scattered density fit: sample " + std::to_string(s) + " has a parameter outside [0, 1]");
  if (!(options.max_rms_rel > 0.0)) throw Error("scattered density fit: max_rms_rel must be > 0");
  if (options.max_control_points != 0 && options.max_control_points < 64)
    throw Error("scattered density fit: max_control_points must be 0 (automatic) or >= 64");
  if (!(options.min_gain_rate >= 0.0) || !(options.min_level_growth >= 0.0 && options.min_level_growth < 1.0))
    throw Error("scattered density fit: min_gain_rate must be >= 0 and min_level_growth in [0, 1)");
  const int budget = options.max_control_points > 0 ? options.max_control_points
                                                    : automatic_control_point_budget(static_cast<std::size_t>(uvw.rows()));
  if (!(options.marking_fraction > 0.0 && options.marking_fraction <= 1.0))
    throw Error("scattered density fit: marking_fraction must be in (0, 1]");
  if (options.max_levels < 0 || options.initial_cells < 0 || !(options.min_cell_width > 0.0) ||
      !(options.min_decrease_rel >= 0.0 && options.min_decrease_rel < 1.0))
    throw Error("scattered density fit: max_levels, initial_cells >= 0, min_cell_width > 0, min_decrease_rel in [0, 1)");
  if (!(options.fit.tolerance > 0.0) || options.fit.max_iterations < 1 || !(options.fit.regularization > 0.0))
    throw Error("scattered density fit: CG tolerance and regularization must be > 0, max_iterations >= 1");
  const double longest = std::max({dims[0], dims[1], dims[2]}) - 1.0;
  const int first = options.initial_cells > 0 ? options.initial_cells
                                              : std::max(1, static_cast<int>(std::lround(longest / 8.0)));
  std::array<int, 3> cells;
  for (int a = 0; a < 3; ++a)
    cells[a] = std::clamp(static_cast<int>(std::lround(first * (dims[a] - 1.0) / longest)), 1, std::max(1, dims[a] - 1));
  while ((cells[0] + 3) * (cells[1] + 3) * (cells[2] + 3) > budget) {
    const int a = static_cast<int>(std::max_element(cells.begin(), cells.end()) - cells.begin());
    if (cells[a] == 1) break;
    --cells[a];
  }
  const std::vector<double> density(targets.col(3).data(), targets.col(3).data() + targets.rows());
  const auto [mn, mx] = std::minmax_element(density.begin(), density.end());
  const double range = *mx > *mn ? *mx - *mn : 1.0;
  progress.report("fit", 0.0);
  std::array<std::vector<double>, 3> knots;
  for (int a = 0; a < 3; ++a) knots[a] = clamped_uniform(cells[a]);
  const int count = (cells[0] + 3) * (cells[1] + 3) * (cells[2] + 3);
  TSpline current = from_bspline_volume(BsplineVolume(knots, Eigen::MatrixXd::Zero(count, 3)),
                                        TSplineAcceleration::FunctionLists);
  RefinementGrid grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), cells);
  const Eigen::MatrixXd density_target = targets.col(3);
  std::vector<AdaptiveDensityLevel> levels;
  std::vector<double> recon;
  double rms = 0.0;
  auto measure = [&](int cg_iterations) {
    recon = evaluate_column0(current, uvw);
    double sum = 0.0, worst = 0.0;
    for (std::size_t s = 0; s < recon.size(); ++s) {
      const double d = recon[s] - density[s];
      sum += d * d;
      worst = std::max(worst, std::abs(d));
    }
    rms = std::sqrt(sum / static_cast<double>(recon.size())) / range;
    levels.push_back({current.num_functions(), rms, worst / range, cg_iterations, grid.num_leaves()});
  };
  measure(fit_tspline_scattered(current, grid, uvw, density_target, {0}, options.fit).cg_iterations);
  double min_width = 1.0;
  for (int a = 0; a < 3; ++a) min_width = std::min(min_width, options.min_cell_width / std::max(1, dims[a] - 1));
  double growth_per_cell = 0.0;
  FitStopReason stop = FitStopReason::MaxLevels;
  for (int level = 1;; ++level) {
    if (rms <= options.max_rms_rel) {
      stop = FitStopReason::Target;
      break;
    }
    if (level_gain_too_small(levels, options)) {
      stop = FitStopReason::Diminishing;
      break;
    }
    if (level > options.max_levels) break;
    const double room = budget - current.num_functions();
    if (room < std::max(1.0, options.min_level_growth * current.num_functions())) {
      stop = FitStopReason::Budget;
      break;
    }
    progress.report("fit", static_cast<double>(level) / (options.max_levels + 1));
    const std::vector<int> leaf_ids = grid.leaves();
    std::vector<double> sse(static_cast<std::size_t>(leaf_ids.back()) + 1, 0.0);
    for (Eigen::Index s = 0; s < uvw.rows(); ++s) {
      const double d = recon[s] - density[s];
      sse[grid.leaf_of(uvw.row(s).transpose())] += d * d;
    }
    double total = 0.0;
    std::vector<int> candidates;
    for (int id : leaf_ids) {
      total += sse[id];
      if ((grid.cell_max(id) - grid.cell_min(id)).minCoeff() >= 2.0 * min_width && sse[id] > 0.0)
        candidates.push_back(id);
    }
    bool over_budget = false;
    std::vector<int> marked =
        bulk_mark(std::move(candidates), sse, total, options.marking_fraction, room, growth_per_cell, &over_budget);
    if (marked.empty()) {
      stop = over_budget ? FitStopReason::Budget : FitStopReason::NoCells;
      break;
    }
    bool accepted = false;
    while (!marked.empty() && !accepted) {
      std::vector<int> sorted = marked;
      std::sort(sorted.begin(), sorted.end());
      RefinementGrid trial_grid = grid;
      // Counted on plain arrays: a TSpline (with its evaluation grid) is only built for an
      // accepted level, after the coarser one is released, so that one grid exists at a time.
      RefinementGrid::Functions trial =
          trial_grid.split_functions({current.knots(), current.weights(), current.points()}, sorted);
      const int trial_count = static_cast<int>(trial.knots.size());
      if (trial_count <= budget) {
        growth_per_cell = std::max(1.0, static_cast<double>(trial_count - current.num_functions())) /
                          static_cast<double>(sorted.size());
        grid = std::move(trial_grid);
        release(current);
        current = TSpline(std::move(trial.knots), std::move(trial.weights), std::move(trial.points),
                          TSplineAcceleration::FunctionLists);
        measure(fit_tspline_scattered(current, grid, uvw, density_target, {0}, options.fit).cg_iterations);
        accepted = true;
      } else {
        marked.resize(marked.size() / 2);
      }
    }
    if (!accepted) {
      stop = FitStopReason::Budget;
      break;
    }
  }
  progress.report("fit", 1.0);
  // Eq. 5.11: add X, Y, Z, fitted over the final cells.
  const int n = current.num_functions();
  // Warm start: the identity-like guess X ≈ Greville abscissa × extent of the targets.
  Eigen::MatrixXd points = Eigen::MatrixXd::Zero(n, 4);
  const Eigen::RowVector3d lo = targets.leftCols(3).colwise().minCoeff();
  const Eigen::RowVector3d extent = targets.leftCols(3).colwise().maxCoeff() - lo;
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      const LocalKnots& r = current.knots()[i][a];
      points(i, a) = lo(a) + extent(a) * (r[1] + r[2] + r[3]) / 3.0;
    }
  points.col(3) = current.points().col(0);
  std::vector<BlendingKnots> knots_out = current.knots();
  Eigen::VectorXd weights_out = current.weights();
  release(current);
  TSpline out(std::move(knots_out), std::move(weights_out), std::move(points), TSplineAcceleration::FunctionLists);
  fit_tspline_scattered(out, grid, uvw, targets.leftCols(3), {0, 1, 2}, options.fit);
  return {std::move(out), std::move(levels), std::move(recon), stop};
}

}  // namespace volspline::spline
