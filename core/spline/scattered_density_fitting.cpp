// SPDX-License-Identifier: MIT
#include "core/spline/scattered_density_fitting.h"

#include <algorithm>
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
  std::vector<int> offsets(1, 0), cols;
  std::fill(stamp.begin(), stamp.end(), -1);
  for (int i = 0; i < n; ++i) {
    const std::size_t first = cols.size();
    for (int q = groups_of_offset[i]; q < groups_of_offset[i + 1]; ++q) {
      const int g = groups_of[q];
      for (int r = group_ids_offset[g]; r < group_ids_offset[g + 1]; ++r)
        if (stamp[group_ids[r]] != i) {
          stamp[group_ids[r]] = i;
          cols.push_back(group_ids[r]);
        }
    }
    if (stamp[i] != i) cols.push_back(i);
    std::sort(cols.begin() + static_cast<std::ptrdiff_t>(first), cols.end());
    offsets.push_back(static_cast<int>(cols.size()));
  }
  std::vector<double> gram(cols.size(), 0.0);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, k);
  // Pass 2: dense Gram block per leaf group, merged into the sorted rows.
  std::vector<int> local(n, -1);
  for (int g = 0; g < groups; ++g) {
    const int l = group_begin[g];
    const int f = group_ids_offset[g + 1] - group_ids_offset[g];
    const int* gid = group_ids.data() + group_ids_offset[g];
    for (int a = 0; a < f; ++a) local[gid[a]] = a;
    const int rows = start[l + 1] - start[l];
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(rows, f);
    Eigen::MatrixXd t(rows, k);
    for (int r = 0; r < rows; ++r) {
      const int s = order[start[l] + r];
      spline.basis_at(uvw.row(s).transpose(), {0, 0, 0}, ids, values);
      for (std::size_t q = 0; q < ids.size(); ++q) block(r, local[ids[q]]) = spline.weights()(ids[q]) * values[q];
      t.row(r) = targets.row(s);
    }
    const Eigen::MatrixXd local_gram = block.transpose() * block;
    const Eigen::MatrixXd local_rhs = block.transpose() * t;
    for (int a = 0; a < f; ++a) {
      const int i = gid[a];
      rhs.row(i) += local_rhs.row(a);
      int p = offsets[i];
      for (int b = 0; b < f; ++b) {
        while (cols[p] < gid[b]) ++p;
        gram[p] += local_gram(a, b);
      }
    }
  }
  double trace = 0.0;
  for (int i = 0; i < n; ++i)
    for (int p = offsets[i]; p < offsets[i + 1]; ++p)
      if (cols[p] == i) trace += gram[p];
  const double mean = trace > 0.0 ? trace / n : 1.0;
  Eigen::MatrixXd x0(n, k);
  for (int c = 0; c < k; ++c) x0.col(c) = spline.points().col(components[c]);
  for (int i = 0; i < n; ++i)
    for (int p = offsets[i]; p < offsets[i + 1]; ++p)
      if (cols[p] == i) {
        const double ridge = options.regularization * (gram[p] > 0.0 ? gram[p] : mean);
        gram[p] += ridge;
        rhs.row(i) += ridge * x0.row(i);
      }
  const linalg::CsrMatrix a = linalg::CsrMatrix::from_arrays(n, n, std::move(offsets), std::move(cols), std::move(gram));
  const ComponentSolveReport solve =
      solve_components(spline, a, rhs, components, options.tolerance, options.max_iterations);
  ScatteredFitReport report;
  report.unknowns = n;
  report.cg_iterations = solve.cg_iterations;
  report.converged = solve.converged;
  report.normal_nonzeros = a.nnz();
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
  if (options.max_control_points < 64) throw Error("scattered density fit: max_control_points must be >= 64");
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
  while ((cells[0] + 3) * (cells[1] + 3) * (cells[2] + 3) > options.max_control_points) {
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
  for (int level = 1; level <= options.max_levels && rms > options.max_rms_rel; ++level) {
    if (levels.size() >= 2 && rms > (1.0 - options.min_decrease_rel) * levels[levels.size() - 2].rms_rel) break;
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
    auto worse = [&](int a, int b) { return sse[a] != sse[b] ? sse[a] > sse[b] : a < b; };
    std::sort(candidates.begin(), candidates.end(), worse);
    std::vector<int> marked;
    double covered = 0.0;
    for (int id : candidates) {
      if (covered >= options.marking_fraction * total) break;
      marked.push_back(id);
      covered += sse[id];
    }
    if (growth_per_cell > 0.0) {
      const double room = options.max_control_points - current.num_functions();
      const std::size_t affordable = static_cast<std::size_t>(std::max(0.0, 0.9 * room / growth_per_cell));
      if (affordable == 0) break;
      if (marked.size() > affordable) marked.resize(affordable);
    }
    bool accepted = false;
    while (!marked.empty() && !accepted) {
      std::vector<int> sorted = marked;
      std::sort(sorted.begin(), sorted.end());
      RefinementGrid trial_grid = grid;
      TSpline trial = trial_grid.split(current, sorted, TSplineAcceleration::FunctionLists);
      if (trial.num_functions() <= options.max_control_points) {
        growth_per_cell = std::max(1.0, static_cast<double>(trial.num_functions() - current.num_functions())) /
                          static_cast<double>(sorted.size());
        const ScatteredFitReport report = fit_tspline_scattered(trial, trial_grid, uvw, density_target, {0}, options.fit);
        grid = std::move(trial_grid);
        current = std::move(trial);
        measure(report.cg_iterations);
        accepted = true;
      } else {
        marked.resize(marked.size() / 2);
      }
    }
    if (!accepted) break;
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
  TSpline out(current.knots(), current.weights(), std::move(points), TSplineAcceleration::FunctionLists);
  fit_tspline_scattered(out, grid, uvw, targets.leftCols(3), {0, 1, 2}, options.fit);
  return {std::move(out), std::move(levels), std::move(recon)};
}

}  // namespace volspline::spline
