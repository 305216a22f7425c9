// SPDX-License-Identifier: MIT
#include "core/spline/density_fitting.h"

#include <algorithm>
#include <utility>
#include <cassert>
#include <cmath>
#include <numeric>
#include <string>

#include <Eigen/Cholesky>

#include "core/common/error.h"
#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/linalg/parallel_for.h"
#include "core/spline/component_solve.h"
#include "core/spline/hierarchical_refinement.h"

namespace volspline::spline {

namespace {

const char* const kCoordinateName[3] = {"x", "y", "z"};

void check_dims(const std::array<int, 3>& dims) {
  for (int a = 0; a < 3; ++a)
    if (dims[a] < 2)
      throw Error(std::string("density fit: the grid needs at least 2 samples along ") + kCoordinateName[a] +
                  ", got " + std::to_string(dims[a]));
}

// Clamped uniform cubic knots with `count` basis functions on [0, length] (§4.3.1 boundary knots).
std::vector<double> uniform_clamped_knots(int count, double length) {
  const int intervals = count - 3;
  std::vector<double> knots;
  knots.reserve(count + 4);
  for (int k = 0; k < 3; ++k) knots.push_back(0.0);
  for (int k = 0; k <= intervals; ++k) knots.push_back(k == intervals ? length : length * k / intervals);
  for (int k = 0; k < 3; ++k) knots.push_back(length);
  return knots;
}

// n×c matrix of the 1D basis at t = 0..n−1.
Eigen::MatrixXd basis_matrix(const std::vector<double>& knots, int n) {
  const int c = static_cast<int>(knots.size()) - 4;
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n, c);
  for (int i = 0; i < c; ++i) {
    const LocalKnots r = {knots[i], knots[i + 1], knots[i + 2], knots[i + 3], knots[i + 4]};
    const RightEnd end = r[4] == knots.back() ? RightEnd::Closed : RightEnd::Open;
    for (int t = 0; t < n; ++t) b(t, i) = cubic_basis(r, static_cast<double>(t), end);
  }
  return b;
}

// Applies the 1D operator op (rows_out × dims[axis]) along `axis` of the x-fastest array `in`.
std::vector<double> apply_along(const std::vector<double>& in, std::array<int, 3>& dims, int axis,
                                const Eigen::MatrixXd& op) {
  assert(op.cols() == dims[axis]);
  std::array<int, 3> out_dims = dims;
  out_dims[axis] = static_cast<int>(op.rows());
  std::vector<double> out(static_cast<std::size_t>(out_dims[0]) * out_dims[1] * out_dims[2], 0.0);
  const std::size_t stride_in[3] = {1, static_cast<std::size_t>(dims[0]),
                                    static_cast<std::size_t>(dims[0]) * dims[1]};
  const std::size_t stride_out[3] = {1, static_cast<std::size_t>(out_dims[0]),
                                     static_cast<std::size_t>(out_dims[0]) * out_dims[1]};
  std::array<int, 3> other = out_dims;
  other[axis] = 1;
  Eigen::VectorXd line(dims[axis]);
  for (int k = 0; k < other[2]; ++k)
    for (int j = 0; j < other[1]; ++j)
      for (int i = 0; i < other[0]; ++i) {
        const int ijk[3] = {i, j, k};
        std::size_t base_in = 0, base_out = 0;
        for (int a = 0; a < 3; ++a)
          if (a != axis) {
            base_in += ijk[a] * stride_in[a];
            base_out += ijk[a] * stride_out[a];
          }
        for (int t = 0; t < dims[axis]; ++t) line(t) = in[base_in + t * stride_in[axis]];
        const Eigen::VectorXd res = op * line;
        for (int t = 0; t < out_dims[axis]; ++t) out[base_out + t * stride_out[axis]] = res(t);
      }
  dims = out_dims;
  return out;
}

// The 1D basis values of every blending function over the integer sample coordinates of its
// support, with the weight w_i folded into the x factor (so the product is the column w_i B_i).
struct Supports {
  std::vector<std::array<int, 3>> lo, hi;          // inclusive sample ranges; hi < lo if empty
  std::vector<std::array<std::size_t, 3>> offset;  // into values
  std::vector<double> values;

  bool empty(int i) const { return hi[i][0] < lo[i][0] || hi[i][1] < lo[i][1] || hi[i][2] < lo[i][2]; }
  const double* at(int i, int a) const { return values.data() + offset[i][a]; }
};

Supports compute_supports(const std::vector<BlendingKnots>& knots, const Eigen::VectorXd& weights,
                          const Eigen::Vector3d& dmax, const std::array<int, 3>& dims) {
  const int n = static_cast<int>(knots.size());
  Supports s;
  s.lo.resize(n);
  s.hi.resize(n);
  s.offset.resize(n);
  for (int i = 0; i < n; ++i) {
    const BlendingKnots& k = knots[i];
    for (int a = 0; a < 3; ++a) {
      const LocalKnots& r = k[a];
      const bool closed = r[4] == dmax(a);
      int lo = static_cast<int>(std::ceil(r[0]));
      int hi = closed ? static_cast<int>(std::floor(r[4])) : static_cast<int>(std::ceil(r[4])) - 1;
      lo = std::max(lo, 0);
      hi = std::min(hi, dims[a] - 1);
      s.lo[i][a] = lo;
      s.hi[i][a] = hi;
      s.offset[i][a] = s.values.size();
      const double scale = a == 0 ? weights(i) : 1.0;
      for (int t = lo; t <= hi; ++t)
        s.values.push_back(scale * cubic_basis(r, static_cast<double>(t), closed ? RightEnd::Closed : RightEnd::Open));
    }
  }
  return s;
}

double dot_overlap(const Supports& s, int i, int j, int a, int lo, int hi) {
  const double* p = s.at(i, a) + (lo - s.lo[i][a]);
  const double* q = s.at(j, a) + (lo - s.lo[j][a]);
  double sum = 0.0;
  for (int t = 0; t <= hi - lo; ++t) sum += p[t] * q[t];
  return sum;
}

// Σ_s f(s) w_i B_i(s) over the support of i.
double project(const Supports& s, int i, const std::vector<double>& f, const std::array<int, 3>& dims) {
  const int* lo = s.lo[i].data();
  const int* hi = s.hi[i].data();
  const double* nx = s.at(i, 0);
  const double* ny = s.at(i, 1);
  const double* nz = s.at(i, 2);
  double total = 0.0;
  for (int z = lo[2]; z <= hi[2]; ++z) {
    double plane = 0.0;
    for (int y = lo[1]; y <= hi[1]; ++y) {
      const double* row = f.data() + static_cast<std::size_t>(dims[0]) * (y + static_cast<std::size_t>(dims[1]) * z);
      double line = 0.0;
      for (int x = lo[0]; x <= hi[0]; ++x) line += row[x] * nx[x - lo[0]];
      plane += line * ny[y - lo[1]];
    }
    total += plane * nz[z - lo[2]];
  }
  return total;
}

// Σ_i c_i w_i B_i at every sample. Slabs of z planes are filled in parallel, each summing the
// functions in increasing i as one pass would: the same bits for every thread count.
std::vector<double> accumulate(const Supports& s, const Eigen::Ref<const Eigen::VectorXd>& coefficients,
                               const std::array<int, 3>& dims, int threads) {
  std::vector<double> out(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2], 0.0);
  constexpr int kSlab = 4;
  linalg::parallel_for(threads, (dims[2] + kSlab - 1) / kSlab, [&](int slab) {
    const int slab_lo = slab * kSlab, slab_hi = std::min(dims[2] - 1, slab_lo + kSlab - 1);
    for (int i = 0; i < static_cast<int>(s.lo.size()); ++i) {
      if (s.empty(i) || coefficients(i) == 0.0) continue;
      const int* lo = s.lo[i].data();
      const int* hi = s.hi[i].data();
      if (hi[2] < slab_lo || lo[2] > slab_hi) continue;
      const double* nx = s.at(i, 0);
      const double* ny = s.at(i, 1);
      const double* nz = s.at(i, 2);
      for (int z = std::max(lo[2], slab_lo); z <= std::min(hi[2], slab_hi); ++z) {
        const double cz = coefficients(i) * nz[z - lo[2]];
        if (cz == 0.0) continue;
        for (int y = lo[1]; y <= hi[1]; ++y) {
          const double cy = cz * ny[y - lo[1]];
          double* row = out.data() + static_cast<std::size_t>(dims[0]) * (y + static_cast<std::size_t>(dims[1]) * z);
          for (int x = lo[0]; x <= hi[0]; ++x) row[x] += cy * nx[x - lo[0]];
        }
      }
    }
  });
  return out;
}

// Normal matrix G_ij = Σ_s w_i B_i(s) w_j B_j(s) = Π_a Σ_t N_i^a(t) N_j^a(t) (tensor grid of
// samples): only the diagonal and the upper triangle (j ≥ i), which is all that CG and its
// preconditioner read, so the matrix costs half the bytes and half the products. Neighbours are
// found through buckets of 8 samples per axis.
linalg::CsrMatrix gram_upper(const Supports& s, const std::array<int, 3>& dims, double ridge_rel,
                             std::vector<double>& ridge, int threads) {
  const int n = static_cast<int>(s.lo.size());
  constexpr int kBucket = 8;
  std::array<int, 3> nb;
  for (int a = 0; a < 3; ++a) nb[a] = (dims[a] + kBucket - 1) / kBucket;
  std::vector<int> bucket_offsets(static_cast<std::size_t>(nb[0]) * nb[1] * nb[2] + 1, 0), bucket_ids;
  auto for_buckets = [&](int i, auto&& visit) {
    for (int z = s.lo[i][2] / kBucket; z <= s.hi[i][2] / kBucket; ++z)
      for (int y = s.lo[i][1] / kBucket; y <= s.hi[i][1] / kBucket; ++y)
        for (int x = s.lo[i][0] / kBucket; x <= s.hi[i][0] / kBucket; ++x)
          visit(x + nb[0] * (y + static_cast<std::size_t>(nb[1]) * z));
  };
  for (int i = 0; i < n; ++i)
    if (!s.empty(i)) for_buckets(i, [&](std::size_t b) { ++bucket_offsets[b + 1]; });
  for (std::size_t b = 1; b < bucket_offsets.size(); ++b) bucket_offsets[b] += bucket_offsets[b - 1];
  bucket_ids.resize(bucket_offsets.back());
  {
    std::vector<int> fill(bucket_offsets.begin(), bucket_offsets.end() - 1);
    for (int i = 0; i < n; ++i)
      if (!s.empty(i)) for_buckets(i, [&](std::size_t b) { bucket_ids[fill[b]++] = i; });
  }
  // Rows are independent: fixed row ranges are built apart and concatenated in order.
  constexpr int kRows = 256;
  const int chunks = (n + kRows - 1) / kRows;
  std::vector<std::vector<int>> chunk_cols(static_cast<std::size_t>(chunks));
  std::vector<std::vector<double>> chunk_values(static_cast<std::size_t>(chunks));
  std::vector<int> row_size(static_cast<std::size_t>(n));
  linalg::parallel_for(threads, chunks, [&](int chunk) {
    std::vector<int> stamp(static_cast<std::size_t>(n), -1);
    std::vector<int> row;
    std::vector<int>& cols = chunk_cols[chunk];
    std::vector<double>& values = chunk_values[chunk];
    for (int i = chunk * kRows; i < std::min(n, (chunk + 1) * kRows); ++i) {
      const std::size_t first = cols.size();
      row.clear();
      row.push_back(i);
      if (!s.empty(i)) {
        stamp[i] = i;
        for_buckets(i, [&](std::size_t b) {
          for (int q = bucket_offsets[b]; q < bucket_offsets[b + 1]; ++q) {
            const int j = bucket_ids[q];
            if (j <= i || stamp[j] == i) continue;
            stamp[j] = i;
            row.push_back(j);
          }
        });
        std::sort(row.begin() + 1, row.end());
      }
      for (int j : row) {
        double product = 1.0;
        if (s.empty(i)) product = 0.0;
        for (int a = 0; a < 3 && product != 0.0; ++a) {
          const int lo = std::max(s.lo[i][a], s.lo[j][a]);
          const int hi = std::min(s.hi[i][a], s.hi[j][a]);
          product = lo > hi ? 0.0 : product * dot_overlap(s, i, j, a, lo, hi);
        }
        if (product != 0.0 || j == i) {
          cols.push_back(j);
          values.push_back(product);
        }
      }
      row_size[i] = static_cast<int>(cols.size() - first);
    }
  });
  std::vector<int> offsets(static_cast<std::size_t>(n) + 1, 0), cols;
  std::vector<double> values;
  for (int i = 0; i < n; ++i) offsets[i + 1] = offsets[i] + row_size[i];
  cols.reserve(static_cast<std::size_t>(offsets[n]));
  values.reserve(static_cast<std::size_t>(offsets[n]));
  for (int c = 0; c < chunks; ++c) {
    cols.insert(cols.end(), chunk_cols[c].begin(), chunk_cols[c].end());
    values.insert(values.end(), chunk_values[c].begin(), chunk_values[c].end());
    std::vector<int>().swap(chunk_cols[c]);
    std::vector<double>().swap(chunk_values[c]);
  }
  // Ridge relative to each diagonal entry (the mean one for unsampled functions): keeps G SPD
  // and CG fast where refined cells hold about one sample per knot interval (nearly dependent
  // columns). The diagonal is the first entry of every row.
  double trace = 0.0;
  for (int i = 0; i < n; ++i) trace += values[offsets[i]];
  const double mean = trace > 0.0 ? trace / n : 1.0;
  ridge.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double& d = values[offsets[i]];
    ridge[i] = ridge_rel * (d > 0.0 ? d : mean);
    d += ridge[i];
  }
  return linalg::CsrMatrix::from_arrays(n, n, std::move(offsets), std::move(cols), std::move(values));
}

}  // namespace

int automatic_control_point_budget(std::size_t num_samples) {
  return static_cast<int>(std::clamp<std::size_t>(num_samples / 16, 64, 50000));
}

bool level_gain_too_small(const std::vector<AdaptiveDensityLevel>& levels, const AdaptiveDensityOptions& options) {
  if (levels.size() < 2) return false;
  const AdaptiveDensityLevel& before = levels[levels.size() - 2];
  const AdaptiveDensityLevel& last = levels.back();
  if (last.rms_rel > (1.0 - options.min_decrease_rel) * before.rms_rel) return true;
  if (options.min_gain_rate <= 0.0 || last.control_points <= before.control_points) return false;
  const double rate = std::log(before.rms_rel / last.rms_rel) /
                      std::log(static_cast<double>(last.control_points) / before.control_points);
  return rate < options.min_gain_rate;
}

std::optional<FitStopReason> adaptive_stop(double rms_rel, const std::vector<AdaptiveDensityLevel>& levels, int level,
                                           int count, int budget, const AdaptiveDensityOptions& options) {
  if (rms_rel <= options.max_rms_rel) return FitStopReason::Target;
  if (level_gain_too_small(levels, options)) return FitStopReason::Diminishing;
  if (level > options.max_levels) return FitStopReason::MaxLevels;
  const double room = static_cast<double>(budget) - count;
  if (room < std::max(1.0, options.min_level_growth * count)) return FitStopReason::Budget;
  return std::nullopt;
}

GridError grid_error(const GridSamples& samples, const std::vector<double>& reconstruction) {
  assert(samples.values.size() == reconstruction.size());
  GridError e;
  if (samples.values.empty()) return e;
  const auto [mn, mx] = std::minmax_element(samples.values.begin(), samples.values.end());
  const double range = *mx > *mn ? *mx - *mn : 1.0;
  double sum = 0.0, worst = 0.0;
  for (std::size_t s = 0; s < reconstruction.size(); ++s) {
    const double d = reconstruction[s] - samples.values[s];
    sum += d * d;
    worst = std::max(worst, std::abs(d));
  }
  e.rms_rel = std::sqrt(sum / static_cast<double>(reconstruction.size())) / range;
  e.max_rel = worst / range;
  return e;
}

UniformBsplineFit fit_uniform_bspline(const GridSamples& samples, const std::array<int, 3>& control_points) {
  check_dims(samples.dims);
  assert(samples.values.size() == static_cast<std::size_t>(samples.dims[0]) * samples.dims[1] * samples.dims[2]);
  std::array<std::vector<double>, 3> knots;
  std::array<Eigen::MatrixXd, 3> basis, pseudo_inverse;
  for (int a = 0; a < 3; ++a) {
    if (control_points[a] < 4)
      throw Error(std::string("uniform B-spline fit: needs at least 4 control points along ") + kCoordinateName[a]);
    if (control_points[a] > samples.dims[a])
      throw Error(std::string("uniform B-spline fit: ") + std::to_string(control_points[a]) +
                  " control points along " + kCoordinateName[a] + " but only " + std::to_string(samples.dims[a]) +
                  " samples");
    knots[a] = uniform_clamped_knots(control_points[a], samples.dims[a] - 1.0);
    basis[a] = basis_matrix(knots[a], samples.dims[a]);
    const Eigen::MatrixXd normal = basis[a].transpose() * basis[a];
    pseudo_inverse[a] = normal.ldlt().solve(basis[a].transpose());
  }
  // (B_z ⊗ B_y ⊗ B_x)⁺ = B_z⁺ ⊗ B_y⁺ ⊗ B_x⁺ for full-column-rank factors.
  std::array<int, 3> dims = samples.dims;
  std::vector<double> coef = samples.values;
  for (int a = 0; a < 3; ++a) coef = apply_along(coef, dims, a, pseudo_inverse[a]);
  std::vector<double> recon = coef;
  for (int a = 0; a < 3; ++a) recon = apply_along(recon, dims, a, basis[a]);
  Eigen::MatrixXd points(static_cast<Eigen::Index>(coef.size()), 1);
  for (std::size_t i = 0; i < coef.size(); ++i) points(static_cast<Eigen::Index>(i), 0) = coef[i];
  const GridError error = grid_error(samples, recon);
  return {BsplineVolume(std::move(knots), std::move(points)), std::move(recon), error};
}

namespace {

// Least-squares fit of columns components[c] of functions.points to targets[c] (fit_tspline_to_grid on
// plain arrays); supports are those of the functions.
GridFitResult fit_functions_to_grid(RefinementGrid::Functions& functions, const Supports& s,
                                    const std::array<int, 3>& dims, const std::vector<int>& components,
                                    const std::vector<const std::vector<double>*>& targets,
                                    const GridFitOptions& options) {
  assert(components.size() == targets.size());
  const int n = static_cast<int>(functions.knots.size());
  const int k = static_cast<int>(components.size());
  std::vector<double> ridge;
  const int threads = std::max(1, options.threads);
  linalg::CsrMatrix gram = gram_upper(s, dims, options.regularization, ridge, threads);
  Eigen::MatrixXd rhs(n, k), x(n, k);
  for (int c = 0; c < k; ++c) {
    assert(targets[c]->size() == static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
    x.col(c) = functions.points.col(components[c]);
    linalg::parallel_for(threads, (n + 255) / 256, [&](int chunk) {
      for (int i = chunk * 256; i < std::min(n, (chunk + 1) * 256); ++i)
        rhs(i, c) = (s.empty(i) ? 0.0 : project(s, i, *targets[c], dims)) + ridge[i] * x(i, c);
    });
  }
  GridFitResult report;
  report.unknowns = n;
  report.normal_nonzeros = 2LL * gram.nnz() - n;  // both triangles
  const ComponentSolveResult solve =
      solve_normal_equations(std::move(gram), rhs, x, options.tolerance, options.max_iterations, threads);
  for (int c = 0; c < k; ++c) functions.points.col(components[c]) = x.col(c);
  report.cg_iterations = solve.cg_iterations;
  report.converged = solve.converged;
  return report;
}

}  // namespace

GridFitResult fit_tspline_to_grid(TSpline& spline, const std::array<int, 3>& dims,
                                  const std::vector<int>& components,
                                  const std::vector<const std::vector<double>*>& targets,
                                  const GridFitOptions& options) {
  RefinementGrid::Functions functions{spline.knots(), spline.weights(), spline.points()};
  const Supports s = compute_supports(functions.knots, functions.weights, spline.domain_max(), dims);
  const GridFitResult report = fit_functions_to_grid(functions, s, dims, components, targets, options);
  if (spline.has_cell_polynomials())
    spline = TSpline(spline.knots(), spline.weights(), std::move(functions.points), TSplineAcceleration::FunctionLists);
  else
    spline.set_points(std::move(functions.points));
  return report;
}

std::vector<double> evaluate_on_grid(const TSpline& spline, int component, const std::array<int, 3>& dims) {
  const Supports s = compute_supports(spline.knots(), spline.weights(), spline.domain_max(), dims);
  return accumulate(s, spline.points().col(component), dims, 1);
}

namespace {

// run_hierarchical_fitting on grid samples: the least-squares grid fit of the density (column 0 of the
// functions' points) and Dörfler marking of the leaves' squared error within the budget.
class DensityGridFit final : public HierarchicalFit, public BudgetedBulkMarking {
 public:
  DensityGridFit(const GridSamples& samples, const AdaptiveDensityOptions& options, int budget,
                 const Eigen::Vector3d& hi, RefinementGrid grid, RefinementGrid::Functions functions,
                 const Progress& progress)
      : grid(std::move(grid)), current(std::move(functions)), samples_(samples), options_(options),
        budget_(budget), hi_(hi), progress_(progress) {}

  void fit(int) override {
    const Supports s = compute_supports(current.knots, current.weights, hi_, samples_.dims);
    const GridFitResult report = fit_functions_to_grid(current, s, samples_.dims, {0}, {&samples_.values}, options_.fit);
    recon = accumulate(s, current.points.col(0), samples_.dims, options_.fit.threads);
    error = grid_error(samples_, recon);
    levels.push_back({num_control_points(), error.rms_rel, error.max_rel, report.cg_iterations, grid.num_leaves()});
  }

  int num_control_points() const override { return static_cast<int>(current.knots.size()); }

  bool refine(const std::vector<int>& cells, int) override {
    RefinementGrid trial_grid = grid;
    RefinementGrid::Functions trial = trial_grid.split_functions(current, cells);
    if (static_cast<int>(trial.knots.size()) > budget_) return false;
    grid = std::move(trial_grid);
    current = std::move(trial);
    return true;
  }

  std::optional<FitStopReason> stop(int level) override {
    return adaptive_stop(error.rms_rel, levels, level + 1, num_control_points(), budget_, options_);
  }

  Marking mark(int level) override {
    progress_.report("fit", static_cast<double>(level + 1) / (options_.max_levels + 1));
    // Dörfler marking (§4.3.3 refines cells over the threshold; here the cells carrying the
    // given fraction of the squared error, which spends control points where the RMS is made).
    const std::array<int, 3>& dims = samples_.dims;
    const std::vector<int> leaf_ids = grid.leaves();
    std::vector<double> sse_of_node(static_cast<std::size_t>(leaf_ids.back()) + 1, 0.0);
    for (int z = 0; z < dims[2]; ++z)
      for (int y = 0; y < dims[1]; ++y)
        for (int x = 0; x < dims[0]; ++x) {
          const std::size_t v = static_cast<std::size_t>(x) + dims[0] * (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims[1]) * z);
          const double d = recon[v] - samples_.values[v];
          if (d != 0.0) sse_of_node[grid.leaf_of(Eigen::Vector3d(x, y, z))] += d * d;
        }
    std::vector<int> candidates;
    double total = 0.0;
    for (int id : leaf_ids) {
      const Eigen::Vector3d width = grid.cell_max(id) - grid.cell_min(id);
      if (width.minCoeff() >= 2.0 * options_.min_cell_width && sse_of_node[id] > 0.0) {
        candidates.push_back(id);
        total += sse_of_node[id];
      }
    }
    // Budget: predict the new control points from the last split's cost per cell (splits are
    // expensive to undo); a level that still ends over budget is retried with fewer cells.
    return mark_within_budget(std::move(candidates), sse_of_node, total, options_.marking_fraction,
                              static_cast<double>(budget_) - num_control_points());
  }

  RefinementGrid grid;
  RefinementGrid::Functions current;
  std::vector<AdaptiveDensityLevel> levels;
  std::vector<double> recon;
  GridError error;

 private:
  const GridSamples& samples_;
  const AdaptiveDensityOptions& options_;
  const int budget_;
  const Eigen::Vector3d hi_;
  const Progress& progress_;
};

}  // namespace

AdaptiveDensityResult fit_density_adaptive(const GridSamples& samples, const AdaptiveDensityOptions& options,
                                           const Progress& progress) {
  check_dims(samples.dims);
  if (!(options.max_rms_rel > 0.0)) throw Error("density fit: max_rms_rel must be > 0");
  if (options.max_control_points != 0 && options.max_control_points < 64)
    throw Error("density fit: max_control_points must be 0 (automatic) or >= 64");
  if (options.initial_cells < 0) throw Error("density fit: initial_cells must be >= 0");
  if (!(options.min_gain_rate >= 0.0) || !(options.min_level_growth >= 0.0 && options.min_level_growth < 1.0))
    throw Error("density fit: min_gain_rate must be >= 0 and min_level_growth in [0, 1)");
  if (!(options.min_cell_width > 0.0)) throw Error("density fit: min_cell_width must be > 0");
  if (!(options.marking_fraction > 0.0 && options.marking_fraction <= 1.0))
    throw Error("density fit: marking_fraction must be in (0, 1]");
  if (options.max_levels < 0) throw Error("density fit: max_levels must be >= 0");
  if (!(options.min_decrease_rel >= 0.0 && options.min_decrease_rel < 1.0))
    throw Error("density fit: min_decrease_rel must be in [0, 1)");
  if (!(options.fit.tolerance > 0.0) || options.fit.max_iterations < 1 || !(options.fit.regularization > 0.0))
    throw Error("density fit: CG tolerance and regularization must be > 0, max_iterations >= 1");
  if (options.fit.threads < 1) throw Error("density fit: threads must be >= 1");
  const std::array<int, 3>& dims = samples.dims;
  const int budget = options.max_control_points > 0 ? options.max_control_points
                                                    : automatic_control_point_budget(samples.values.size());
  const Eigen::Vector3d hi(dims[0] - 1.0, dims[1] - 1.0, dims[2] - 1.0);
  // Level 0: 2^k uniform cells per axis made by splitting one cell k times, so that every knot
  // is a dyadic point of the domain and the refinement tree has a single root (ray tracing in
  // RefinementGrid then only descends the cells along each ray).
  const int wanted = options.initial_cells > 0 ? options.initial_cells
                                               : std::max(1, static_cast<int>(std::lround(hi.maxCoeff() / 8.0)));
  int splits = 0;
  while ((1 << (splits + 1)) <= wanted && splits < 8) ++splits;
  auto cube = [](int c) { return static_cast<long long>(c + 3) * (c + 3) * (c + 3); };
  while (splits > 0 && cube(1 << splits) > budget) --splits;
  progress.report("fit", 0.0);
  // Eq. 5.11 with the identity parameterization: X, Y, Z are the sample positions. The cubic
  // Bézier cell with control points at thirds reproduces them, and knot insertion keeps F, so
  // the splits carry their exact control points along with the density's (columns 1..3).
  // The refinement works on plain arrays: the grid fit needs only the knots, and a TSpline's
  // evaluation grid at every level would cost more time and memory than the fit itself.
  std::array<std::vector<double>, 3> knots;
  Eigen::MatrixXd bezier_points(64, 4);
  for (int a = 0; a < 3; ++a) knots[a] = {0.0, 0.0, 0.0, 0.0, hi(a), hi(a), hi(a), hi(a)};
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) bezier_points.row(i + 4 * (j + 4 * k)) << 0.0, hi(0) * i / 3.0, hi(1) * j / 3.0, hi(2) * k / 3.0;
  RefinementGrid::Functions current;
  {
    const TSpline bezier = from_bspline_volume(BsplineVolume(knots, bezier_points), TSplineAcceleration::FunctionLists);
    current = {bezier.knots(), bezier.weights(), bezier.points()};
  }
  RefinementGrid grid(Eigen::Vector3d::Zero(), hi, {1, 1, 1});
  for (int k = 0; k < splits; ++k) current = grid.split_functions(current, grid.leaves());
  DensityGridFit fit(samples, options, budget, hi, std::move(grid), std::move(current), progress);
  const HierarchicalFitResult run = run_hierarchical_fitting(fit, fit);
  RefinementGrid::Functions& current_fit = fit.current;
  progress.report("fit", 1.0);
  // Output layout (X, Y, Z, density).
  Eigen::MatrixXd points(current_fit.points.rows(), 4);
  points.leftCols(3) = current_fit.points.rightCols(3);
  points.col(3) = current_fit.points.col(0);
  TSpline out(std::move(current_fit.knots), std::move(current_fit.weights), std::move(points),
              TSplineAcceleration::FunctionLists);
  return {std::move(out), std::move(fit.levels), std::move(fit.recon), fit.error, fit.grid.max_level(),
          run.stop_reason};
}

}  // namespace volspline::spline
