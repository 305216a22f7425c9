// SPDX-License-Identifier: MIT
#include "core/spline/scattered_density_fitting.h"

#include <algorithm>
#include <unordered_map>
#include <utility>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "core/common/error.h"
#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/linalg/parallel_for.h"
#include "core/spline/component_solve.h"
#include "core/spline/grouped_gram.h"
#include "core/spline/hierarchical_fitting.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/sparsified_cholesky.h"

namespace volspline::spline {

namespace {

std::vector<double> clamped_uniform(int intervals) {
  std::vector<double> k = {0.0, 0.0, 0.0};
  for (int i = 0; i <= intervals; ++i) k.push_back(i == intervals ? 1.0 : static_cast<double>(i) / intervals);
  for (int i = 0; i < 3; ++i) k.push_back(1.0);
  return k;
}

// Samples per work chunk of the per-sample passes (a fixed partition: results never depend on
// the thread count).
constexpr Eigen::Index kSampleChunk = 4096;

int sample_chunks(Eigen::Index m) { return static_cast<int>((m + kSampleChunk - 1) / kSampleChunk); }

// The density (component 3) of the spline at every sample.
std::vector<double> evaluate_density(const TSpline& spline, const Eigen::MatrixX3d& uvw, int threads) {
  std::vector<double> out(static_cast<std::size_t>(uvw.rows()));
  linalg::parallel_for(threads, sample_chunks(uvw.rows()), [&](int chunk) {
    double value[4];
    const Eigen::Index end = std::min(uvw.rows(), (chunk + 1) * kSampleChunk);
    for (Eigen::Index s = chunk * kSampleChunk; s < end; ++s) {
      spline.evaluate_to(uvw.row(s).transpose(), TSplineForm::SemiStandard, value);
      out[static_cast<std::size_t>(s)] = value[3];
    }
  });
  return out;
}

// Normal equations MᵀM x = Mᵀt of a least-squares fit (Eq. 3.5/3.6): the upper triangle of
// MᵀM plus a ridge on its diagonal, Mᵀt for every target column, and the ridge per row (the
// caller adds ridge ∘ x0, which pulls the solution towards its warm start x0).
struct NormalEquations {
  linalg::CsrMatrix gram;
  Eigen::MatrixXd rhs;
  Eigen::VectorXd ridge;
};

// 64-bit FNV-1a of a function id list.
std::uint64_t hash_ids(const std::vector<int>& ids) {
  std::uint64_t h = 1469598103934665603ULL;
  for (int id : ids) {
    h ^= static_cast<std::uint32_t>(id);
    h *= 1099511628211ULL;
  }
  return h;
}

// Samples grouped by their list of blending functions, each group's list in
// group_ids_offset/group_ids: every sample of a knot-line cell has the cell's list
// (TSpline::cell_functions), and cells with equal lists form one group, so only one list per
// occupied cell is looked at. Groups are numbered in order of their first cell's first sample.
struct SampleGroups {
  std::vector<int> group;  // per sample
  std::vector<int> group_ids_offset{0}, group_ids;
};

SampleGroups group_samples(const TSpline& spline, const Eigen::MatrixX3d& uvw, int threads) {
  const Eigen::Index m = uvw.rows();
  // (cell, sample) keys, sorted: the occupied cells with their samples in increasing order.
  std::vector<std::uint64_t> key(static_cast<std::size_t>(m));
  linalg::parallel_for(threads, sample_chunks(m), [&](int chunk) {
    const Eigen::Index end = std::min(m, (chunk + 1) * kSampleChunk);
    for (Eigen::Index s = chunk * kSampleChunk; s < end; ++s)
      key[static_cast<std::size_t>(s)] =
          (static_cast<std::uint64_t>(spline.cell_of(uvw.row(s).transpose())) << 32) | static_cast<std::uint64_t>(s);
  });
  std::sort(key.begin(), key.end());
  // Cells by their first sample, so that group numbers follow the samples.
  std::vector<std::pair<int, std::size_t>> cells;  // (first sample, first key)
  for (std::size_t q = 0; q < key.size(); ++q)
    if (q == 0 || (key[q] >> 32) != (key[q - 1] >> 32)) cells.emplace_back(static_cast<int>(key[q] & 0xffffffffu), q);
  std::sort(cells.begin(), cells.end());
  SampleGroups out;
  out.group.resize(static_cast<std::size_t>(m));
  std::unordered_map<std::uint64_t, std::vector<int>> groups_of_hash;  // lookups only
  std::vector<int> ids;
  for (const auto& [first_sample, first_key] : cells) {
    const std::uint64_t cell = key[first_key] >> 32;
    spline.cell_functions(static_cast<int>(cell), ids);
    std::vector<int>& candidates = groups_of_hash[hash_ids(ids)];
    int g = -1;
    for (int c : candidates)
      if (std::equal(ids.begin(), ids.end(), out.group_ids.begin() + out.group_ids_offset[c],
                     out.group_ids.begin() + out.group_ids_offset[c + 1])) {
        g = c;
        break;
      }
    if (g < 0) {
      g = static_cast<int>(out.group_ids_offset.size()) - 1;
      candidates.push_back(g);
      out.group_ids.insert(out.group_ids.end(), ids.begin(), ids.end());
      out.group_ids_offset.push_back(static_cast<int>(out.group_ids.size()));
    }
    for (std::size_t q = first_key; q < key.size() && (key[q] >> 32) == cell; ++q)
      out.group[static_cast<std::size_t>(key[q] & 0xffffffffu)] = g;
  }
  return out;
}

// Every sample of one knot-line cell of the T-spline has the same blending functions, so
// samples are grouped by that list (group_samples) and each group adds one dense Gram block, a
// symmetric rank update, to the sparse upper triangle. Groups run in Morton order of their first
// sample, so consecutive groups touch neighbouring rows.
NormalEquations assemble_normal_equations(const TSpline& spline, const Eigen::MatrixX3d& uvw,
                                          const Eigen::MatrixXd& targets, double regularization, int threads) {
  const int n = spline.num_functions();
  const Eigen::Index m = uvw.rows();
  const Eigen::Index k = targets.cols();
  SampleGroups grouping = group_samples(spline, uvw, threads);
  std::vector<int>& group = grouping.group;
  std::vector<int>& group_ids_offset = grouping.group_ids_offset;
  std::vector<int>& group_ids = grouping.group_ids;
  const int groups = static_cast<int>(group_ids_offset.size()) - 1;
  // Groups in Morton order of their first sample's parameters: consecutive groups share most
  // functions, so the scatter below stays within a few cached rows.
  {
    std::vector<std::pair<std::uint64_t, int>> key(static_cast<std::size_t>(groups));
    std::vector<char> seen(static_cast<std::size_t>(groups), 0);
    for (Eigen::Index s = 0; s < m; ++s) {
      const int g = group[static_cast<std::size_t>(s)];
      if (seen[g]) continue;
      seen[g] = 1;
      std::uint64_t code = 0;
      std::uint32_t q[3];
      for (int a = 0; a < 3; ++a) q[a] = static_cast<std::uint32_t>(std::clamp(uvw(s, a), 0.0, 1.0) * 1023.0);
      for (int bit = 9; bit >= 0; --bit)
        for (int a = 2; a >= 0; --a) code = (code << 1) | ((q[a] >> bit) & 1u);
      key[g] = {code, g};
    }
    std::sort(key.begin(), key.end());
    std::vector<int> renumber(static_cast<std::size_t>(groups)), ids_offset(1, 0), ids_sorted;
    ids_sorted.reserve(group_ids.size());
    for (int g = 0; g < groups; ++g) {
      const int old = key[g].second;
      renumber[old] = g;
      ids_sorted.insert(ids_sorted.end(), group_ids.begin() + group_ids_offset[old],
                        group_ids.begin() + group_ids_offset[old + 1]);
      ids_offset.push_back(static_cast<int>(ids_sorted.size()));
    }
    group_ids = std::move(ids_sorted);
    group_ids_offset = std::move(ids_offset);
    for (int& g : group) g = renumber[g];
  }
  // Samples by group (counting sort, stable: deterministic).
  std::vector<int> sample_start(static_cast<std::size_t>(groups) + 1, 0), order(static_cast<std::size_t>(m));
  for (int g : group) ++sample_start[g + 1];
  for (int g = 0; g < groups; ++g) sample_start[g + 1] += sample_start[g];
  {
    std::vector<int> fill(sample_start.begin(), sample_start.end() - 1);
    for (Eigen::Index s = 0; s < m; ++s) order[fill[group[s]]++] = static_cast<int>(s);
  }
  std::vector<int>().swap(group);
  GroupedGram normal(n, static_cast<int>(k), std::move(group_ids_offset), std::move(group_ids), threads);
  std::vector<int> row_counts(static_cast<std::size_t>(groups));
  for (int g = 0; g < groups; ++g) row_counts[g] = sample_start[g + 1] - sample_start[g];
  normal.add_all(row_counts, [&](int g, Eigen::MatrixXd& block, Eigen::MatrixXd& t) {
    const int f = normal.group_size(g);
    [[maybe_unused]] const int* list = normal.group_columns(g);
    const int rows = sample_start[g + 1] - sample_start[g];
    block.resize(rows, f);
    t.resize(rows, k);
    std::vector<int> ids;
    std::vector<double> values;
    for (int r = 0; r < rows; ++r) {
      const int s = order[sample_start[g] + r];
      spline.basis_at(uvw.row(s).transpose(), {0, 0, 0}, ids, values);
      assert(static_cast<int>(ids.size()) == f && std::equal(ids.begin(), ids.end(), list));
      for (int q = 0; q < f; ++q) block(r, q) = spline.weights()(ids[q]) * values[q];
      t.row(r) = targets.row(s);
    }
  });
  Eigen::MatrixXd rhs = std::move(normal.rhs());
  // Upper triangle only (the diagonal first in every row): all that CG and its preconditioner
  // read, at half the memory of both triangles.
  linalg::CsrMatrix upper = normal.take_upper();
  const std::vector<int>& offsets = upper.row_offsets();
  std::vector<double>& gram = upper.values();
  double trace = 0.0;
  for (int i = 0; i < n; ++i) trace += gram[offsets[i]];
  const double mean = trace > 0.0 ? trace / n : 1.0;
  Eigen::VectorXd ridge(n);
  for (int i = 0; i < n; ++i) {
    double& d = gram[offsets[i]];
    ridge(i) = regularization * (d > 0.0 ? d : mean);
    d += ridge(i);
  }
  return NormalEquations{std::move(upper), std::move(rhs), std::move(ridge)};
}

// Replaces a spline by a one-function placeholder, freeing its evaluation grid before the next
// spline's is built (TSpline has no empty state).
void release(TSpline& spline) {
  spline = TSpline(std::vector<BlendingKnots>(1, spline.knots()[0]), Eigen::VectorXd::Ones(1),
                   Eigen::MatrixXd::Zero(1, spline.dimension()), TSplineAcceleration::FunctionLists);
}

// run_hierarchical_fitting on scattered samples: the density column (3) fitted by least squares over the
// current cells, with the factorized normal matrix kept for the final geometry fit (Eq. 5.11),
// and Dörfler marking of the leaves' squared error within the budget.
class ScatteredDensityFit final : public HierarchicalFit, public BudgetedBulkMarking {
 public:
  ScatteredDensityFit(const Eigen::MatrixX3d& uvw, const Eigen::MatrixXd& targets, const std::array<int, 3>& dims,
                      const AdaptiveDensityOptions& options, int budget, TSpline spline, RefinementGrid grid,
                      const Progress& progress)
      : current(std::move(spline)), grid(std::move(grid)), uvw_(uvw), targets_(targets), options_(options),
        budget_(budget), threads_(options.fit.threads), progress_(progress),
        density_(targets.col(3).data(), targets.col(3).data() + targets.rows()) {
    const auto [mn, mx] = std::minmax_element(density_.begin(), density_.end());
    range_ = *mx > *mn ? *mx - *mn : 1.0;
    for (int a = 0; a < 3; ++a) min_width_ = std::min(min_width_, options.min_cell_width / std::max(1, dims[a] - 1));
  }

  void fit(int) override {
    NormalEquations eq = assemble_normal_equations(current, uvw_, targets_, options_.fit.regularization, threads_);
    solver = std::make_unique<linalg::ConjugateGradient<SparsifiedCholesky>>();
    solver->set_tolerance(options_.fit.tolerance);
    solver->set_max_iterations(options_.fit.max_iterations);
    solver->set_threads(threads_);
    solver->compute(eq.gram);
    eq.gram = linalg::CsrMatrix();
    const Eigen::VectorXd x0 = current.points().col(3);
    const Eigen::VectorXd x = solver->solve(eq.rhs.col(3) + eq.ridge.cwiseProduct(x0), x0);
    geometry_rhs = eq.rhs.leftCols(3);
    ridge = std::move(eq.ridge);
    Eigen::MatrixXd points = current.points();
    points.col(3) = x;
    current.set_points(std::move(points));
    recon = evaluate_density(current, uvw_, threads_);
    double sum = 0.0, worst = 0.0;
    for (std::size_t s = 0; s < recon.size(); ++s) {
      const double d = recon[s] - density_[s];
      sum += d * d;
      worst = std::max(worst, std::abs(d));
    }
    rms_ = std::sqrt(sum / static_cast<double>(recon.size())) / range_;
    levels.push_back({current.num_functions(), rms_, worst / range_, solver->iterations(), grid.num_leaves()});
  }

  int num_control_points() const override { return current.num_functions(); }

  bool refine(const std::vector<int>& cells, int) override {
    RefinementGrid trial_grid = grid;
    // Counted on plain arrays: a TSpline (with its evaluation grid) is only built for an
    // accepted level, after the coarser one is released, so that one grid exists at a time.
    RefinementGrid::Functions trial =
        trial_grid.split_functions({current.knots(), current.weights(), current.points()}, cells);
    if (static_cast<int>(trial.knots.size()) > budget_) return false;
    grid = std::move(trial_grid);
    solver.reset();
    release(current);
    current = TSpline(std::move(trial.knots), std::move(trial.weights), std::move(trial.points),
                      TSplineAcceleration::FunctionLists);
    return true;
  }

  std::optional<FitStopReason> stop(int level) override {
    return adaptive_stop(rms_, levels, level + 1, current.num_functions(), budget_, options_);
  }

  Marking mark(int level) override {
    progress_.report("fit", static_cast<double>(level + 1) / (options_.max_levels + 1));
    const std::vector<int> leaf_ids = grid.leaves();
    std::vector<double> sse(static_cast<std::size_t>(leaf_ids.back()) + 1, 0.0);
    {
      // Leaves looked up in parallel, squared errors summed in sample order.
      std::vector<int> leaf(static_cast<std::size_t>(uvw_.rows()));
      linalg::parallel_for(threads_, sample_chunks(uvw_.rows()), [&](int chunk) {
        const Eigen::Index end = std::min(uvw_.rows(), (chunk + 1) * kSampleChunk);
        for (Eigen::Index s = chunk * kSampleChunk; s < end; ++s) leaf[s] = grid.leaf_of(uvw_.row(s).transpose());
      });
      for (Eigen::Index s = 0; s < uvw_.rows(); ++s) {
        const double d = recon[s] - density_[s];
        sse[leaf[s]] += d * d;
      }
    }
    double total = 0.0;
    std::vector<int> candidates;
    for (int id : leaf_ids) {
      total += sse[id];
      if ((grid.cell_max(id) - grid.cell_min(id)).minCoeff() >= 2.0 * min_width_ && sse[id] > 0.0)
        candidates.push_back(id);
    }
    return mark_within_budget(std::move(candidates), sse, total, options_.marking_fraction,
                              static_cast<double>(budget_) - current.num_functions());
  }

  TSpline current;
  RefinementGrid grid;
  std::vector<AdaptiveDensityLevel> levels;
  std::vector<double> recon;
  // The normal matrix of the current cells, factorized, and the X, Y, Z right-hand sides:
  // the final geometry fit reuses them (the density and geometry columns share MᵀM).
  std::unique_ptr<linalg::ConjugateGradient<SparsifiedCholesky>> solver;
  Eigen::MatrixXd geometry_rhs;
  Eigen::VectorXd ridge;

 private:
  const Eigen::MatrixX3d& uvw_;
  const Eigen::MatrixXd& targets_;
  const AdaptiveDensityOptions& options_;
  const int budget_;
  const int threads_;
  const Progress& progress_;
  const std::vector<double> density_;
  double range_ = 1.0;
  double min_width_ = 1.0;
  double rms_ = 0.0;
};

}  // namespace

ScatteredFitResult fit_tspline_scattered(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixXd& targets,
                                         const std::vector<int>& components, const GridFitOptions& options) {
  assert(targets.rows() == uvw.rows() && targets.cols() == static_cast<Eigen::Index>(components.size()));
  NormalEquations eq = assemble_normal_equations(spline, uvw, targets, options.regularization, std::max(1, options.threads));
  const int n = spline.num_functions();
  const int k = static_cast<int>(components.size());
  Eigen::MatrixXd x0(n, k);
  for (int c = 0; c < k; ++c) x0.col(c) = spline.points().col(components[c]);
  eq.rhs += eq.ridge.asDiagonal() * x0;
  ScatteredFitResult report;
  report.unknowns = n;
  report.normal_nonzeros = 2LL * eq.gram.nnz() - n;  // both triangles
  const ComponentSolveResult solve =
      solve_components(spline, std::move(eq.gram), eq.rhs, components, options.tolerance, options.max_iterations);
  report.cg_iterations = solve.cg_iterations;
  report.converged = solve.converged;
  return report;
}

ScatteredDensityResult fit_scattered_adaptive(const Eigen::MatrixX3d& uvw, const Eigen::MatrixXd& targets,
                                              const std::array<int, 3>& dims, const AdaptiveDensityOptions& options,
                                              const Progress& progress) {
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
  if (options.fit.threads < 1) throw Error("scattered density fit: threads must be >= 1");
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
  progress.report("fit", 0.0);
  std::array<std::vector<double>, 3> knots;
  for (int a = 0; a < 3; ++a) knots[a] = clamped_uniform(cells[a]);
  const int count = (cells[0] + 3) * (cells[1] + 3) * (cells[2] + 3);
  // Eq. 5.11 with D = 4 from the start: (X, Y, Z) ride along (as zeros) through the knot
  // insertions, so the final spline needs no second evaluation grid.
  TSpline current = from_bspline_volume(BsplineVolume(knots, Eigen::MatrixXd::Zero(count, 4)),
                                        TSplineAcceleration::FunctionLists);
  RefinementGrid grid(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), cells);
  ScatteredDensityFit fit(uvw, targets, dims, options, budget, std::move(current), std::move(grid), progress);
  const HierarchicalFitResult run = run_hierarchical_fitting(fit, fit);
  TSpline& current_fit = fit.current;
  progress.report("fit", 1.0);
  // Eq. 5.11: X, Y, Z fitted over the final cells with the density's normal matrix, warm-started
  // from the identity-like guess X ≈ Greville abscissa × extent of the targets.
  const int n = current_fit.num_functions();
  Eigen::MatrixXd points = current_fit.points();
  const Eigen::RowVector3d lo = targets.leftCols(3).colwise().minCoeff();
  const Eigen::RowVector3d extent = targets.leftCols(3).colwise().maxCoeff() - lo;
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      const LocalKnots& r = current_fit.knots()[i][a];
      points(i, a) = lo(a) + extent(a) * (r[1] + r[2] + r[3]) / 3.0;
    }
  const Eigen::MatrixXd x0 = points.leftCols(3);
  points.leftCols(3) = fit.solver->solve(fit.geometry_rhs + fit.ridge.asDiagonal() * x0, x0);
  fit.solver.reset();
  current_fit.set_points(std::move(points));
  return {std::move(current_fit), std::move(fit.levels), std::move(fit.recon), run.stop_reason};
}

}  // namespace volspline::spline
