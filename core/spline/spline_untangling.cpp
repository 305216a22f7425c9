// SPDX-License-Identifier: MIT
#include "core/spline/spline_untangling.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/LU>

#include "core/param/barrier_untangling.h"
#include "core/spline/bspline_basis.h"
#include "core/spline/tspline_fitting.h"

namespace volspline::spline {

namespace {

// Points at least this good (scaled Jacobian) keep their own Jacobian as the rest shape.
constexpr double kGoodScaledJacobian = 0.1;
// Least share of |w∇B| at a seed the free functions must carry (bunny: seeds below 0.02 stay
// folded, those above 0.3 unfold).
constexpr double kMinMovableShare = 0.1;
// ε shrinks at least this much per step (param::UntangleOptions::min_sigma): 5 steps instead
// of 8 on bunny with 0.5; 0.9 shrinks it faster than the folds open.
constexpr double kMinSigma = 0.75;

double scaled_jacobian(const Eigen::Matrix3d& j) {
  const double norms = j.col(0).norm() * j.col(1).norm() * j.col(2).norm();
  return norms > 0.0 ? j.determinant() / norms : -1.0;
}

// F(x) = fixed + Σ_e x_e b_e at one sample, target xyz.
struct SampleTerm {
  Eigen::Vector3d fixed, target;
  std::vector<std::pair<int, double>> entries;
};

// 3×3 matrices at n nodes, structure of arrays: entry (r, a) of node p at data()[(r + 3a)·n + p].
class MatrixField {
 public:
  explicit MatrixField(std::size_t n = 0) : n_(n), values_(9 * n, 0.0) {}
  std::size_t size() const { return n_; }
  double* data() { return values_.data(); }
  const double* data() const { return values_.data(); }
  Eigen::Matrix3d get(std::size_t p) const {
    Eigen::Matrix3d m;
    for (int e = 0; e < 9; ++e) m.data()[e] = values_[e * n_ + p];
    return m;
  }
  void set(std::size_t p, const Eigen::Matrix3d& m) {
    for (int e = 0; e < 9; ++e) values_[e * n_ + p] = m.data()[e];
  }
  void add(std::size_t p, const Eigen::Matrix3d& m) {
    for (int e = 0; e < 9; ++e) values_[e * n_ + p] += m.data()[e];
  }

 private:
  std::size_t n_;
  std::vector<double> values_;
};

// A free function on the lattice: the box of nodes where it may be non-zero, first[a] ..
// first[a] + count[a] − 1 per axis, and the factors of w·∇B there: w·N_a and w·N_a' per axis
// (the weight folded into axis 0), so w·∇B = (n'₀n₁n₂, n₀n'₁n₂, n₀n₁n'₂).
struct FreeFunction {
  std::array<int, 3> first{}, count{};
  std::array<std::vector<double>, 3> value, slope;
};

// The Jacobians at the region nodes as a fixed linear map of the free control points: the knots
// do not change while untangling, so each evaluation is a sum over the functions' node boxes of
// tensor products (no basis evaluation, no per-node entry lists).
class LatticeJacobians {
 public:
  LatticeJacobians() = default;
  LatticeJacobians(std::vector<FreeFunction> functions, std::vector<int> node_index, int m)
      : functions_(std::move(functions)), node_index_(std::move(node_index)), m_(m) {}

  // jac[p] += Σ_c x_c (w∇B_c(p))ᵀ over the region nodes p (dense: over all m³ energy nodes,
  // jac indexed by node).
  void add(const Eigen::VectorXd& x, MatrixField& jac, bool dense = false) const {
    const std::size_t n = jac.size();
    for (std::size_t c = 0; c < functions_.size(); ++c) {
      const double xc[3] = {x(3 * c), x(3 * c + 1), x(3 * c + 2)};
      for_each_row(functions_[c], dense, [&](int p0, double a, double b, double cc, const FreeFunction& f) {
        const double *slope = f.slope[0].data(), *value = f.value[0].data();
        const int count = f.count[0];
        for (int r = 0; r < 3; ++r) {
          double* j0 = jac.data() + r * n + p0;
          double* j1 = jac.data() + (r + 3) * n + p0;
          double* j2 = jac.data() + (r + 6) * n + p0;
          const double xa = xc[r] * a, xb = xc[r] * b, xcc = xc[r] * cc;
          for (int i = 0; i < count; ++i) {
            j0[i] += xa * slope[i];
            j1[i] += xb * value[i];
            j2[i] += xcc * value[i];
          }
        }
      });
    }
  }

  // gradient_c += Σ_p d[p]·w∇B_c(p), d[p] = ∂E/∂J at node p.
  void add_gradient(const MatrixField& d, Eigen::VectorXd& gradient) const {
    const std::size_t n = d.size();
    for (std::size_t c = 0; c < functions_.size(); ++c) {
      double sum[3] = {0.0, 0.0, 0.0};
      for_each_row(functions_[c], false, [&](int p0, double a, double b, double cc, const FreeFunction& f) {
        const double *slope = f.slope[0].data(), *value = f.value[0].data();
        const int count = f.count[0];
        for (int r = 0; r < 3; ++r) {
          const double* d0 = d.data() + r * n + p0;
          const double* d1 = d.data() + (r + 3) * n + p0;
          const double* d2 = d.data() + (r + 6) * n + p0;
          double s0 = 0.0, s1 = 0.0;
          for (int i = 0; i < count; ++i) {
            s0 += d0[i] * slope[i];
            s1 += d1[i] * b * value[i] + d2[i] * cc * value[i];
          }
          sum[r] += a * s0 + s1;
        }
      });
      for (int r = 0; r < 3; ++r) gradient(3 * c + r) += sum[r];
    }
  }

 private:
  // Calls row(p0, n₁n₂, n'₁n₂, n₁n'₂, f) per lattice row of f's box; p0: the region index of the
  // row's first node (a box row is consecutive in the region order).
  template <class Row>
  void for_each_row(const FreeFunction& f, bool dense, Row&& row) const {
    for (int k = 0; k < f.count[2]; ++k)
      for (int j = 0; j < f.count[1]; ++j) {
        const double v = f.value[1][j], w = f.value[2][k];
        const int node = f.first[0] + m_ * (f.first[1] + j + m_ * (f.first[2] + k));
        const int p0 = dense ? node : node_index_[node];
        row(p0, v * w, f.slope[1][j] * w, v * f.slope[2][k], f);
      }
  }

  std::vector<FreeFunction> functions_;
  std::vector<int> node_index_;  // energy node → region index, −1 outside
  int m_ = 0;
};

// The energy's nodes: J = fixed + lattice(x) at node q, reference shape inverse_reference[q].
struct Region {
  LatticeJacobians lattice;
  MatrixField fixed;
  std::vector<Eigen::Matrix3d> inverse_reference;
  Eigen::Vector3d mean_scale = Eigen::Vector3d::Zero();  // of the column norms of J
  // Nodes that must end unfolded: the scanned ones and those not folded before. A folded node
  // off the scan that the free functions cannot reach (bimba has some) would otherwise hold
  // the ε continuation until its barrier dominates the energy.
  std::vector<char> guarded;
};

// One scan for seeds and one untangling of the points near them.
// result stays as it is: the pass reads and moves `current` (its control points so far), and
// `correction` holds J(current) − J(result) at the energy nodes (empty: none yet).
SplineUntangleReport untangle_pass(const TSpline& result, Eigen::MatrixXd& current,
                                   MatrixField& correction, const Eigen::MatrixX3d& uvw,
                                   const Eigen::MatrixX3d& xyz, const SplineUntangleOptions& options) {
  SplineUntangleReport report;
  const int l = options.lattice, m = l - 1;  // m lattice nodes per axis, index i ↔ (i + 1)/l
  // The energy's nodes: every es-th lattice node per axis, e ↔ lattice node e·es (they hold the
  // scanned ones, es divides seed_stride).
  const int es = options.energy_stride, me = (m - 1) / es + 1;
  const Eigen::Vector3d lo = result.domain_min(), hi = result.domain_max();
  auto point = [&](int i, int j, int k) {
    return Eigen::Vector3d(lo + (hi - lo).cwiseProduct(Eigen::Vector3d(i + 1, j + 1, k + 1) / l));
  };
  // Energy node index of lattice node (i, j, k), each a multiple of es.
  auto index = [&](int i, int j, int k) { return i / es + me * (j / es + me * (k / es)); };
  auto jacobian_at = [&](int i, int j, int k) {
    double value[3];
    Eigen::Matrix3d jac;
    result.evaluate_with_jacobian(point(i, j, k), TSplineForm::SemiStandard, value, jac.data());
    if (correction.size() > 0) jac += correction.get(index(i, j, k));
    return jac;
  };

  // The scanned points: counts of non-positive ones, the minimum, and the seeds (if asked).
  auto scan = [&](std::vector<std::array<int, 3>>* seeds) {
    report.scanned = 0;
    report.final_negative = 0;
    report.final_min_scaled = 1.0;
    for (int k = 0; k < m; k += options.seed_stride)
      for (int j = 0; j < m; j += options.seed_stride)
        for (int i = 0; i < m; i += options.seed_stride) {
          const double q = scaled_jacobian(jacobian_at(i, j, k));
          ++report.scanned;
          if (q <= 0.0) ++report.final_negative;
          if (seeds && q < options.min_scaled_jacobian) seeds->push_back({i, j, k});
          report.final_min_scaled = std::min(report.final_min_scaled, q);
        }
  };
  std::vector<std::array<int, 3>> seeds;
  scan(&seeds);
  report.seeds = static_cast<int>(seeds.size());
  report.initial_negative = report.final_negative;
  if (seeds.empty()) return report;

  // Free functions: interior ones acting near a seed, with supports of at most `limit`
  // lattice steps per axis. A seed whose small interior functions carry less than
  // kMinMovableShare of the gradient there (it lies under boundary functions and coarse ones)
  // cannot be unfolded by them: its limit doubles until they do.
  const int n = result.num_functions();
  const Eigen::VectorXd& w = result.weights();
  std::vector<int> column_of(n, -1), free_ids;
  std::vector<int> ids;
  std::vector<double> values;
  auto support_steps = [&](int f) {
    double steps = 0.0;
    for (int a = 0; a < 3; ++a) {
      const LocalKnots& r = result.knots()[f][a];
      steps = std::max(steps, (r[4] - r[0]) / (hi(a) - lo(a)) * l);
    }
    return steps;
  };
  std::array<std::vector<int>, 3> d_ids;
  std::array<std::vector<double>, 3> d_values;
  for (const auto& s : seeds) {
    for (int a = 0; a < 3; ++a) {
      std::array<int, 3> order = {0, 0, 0};
      order[a] = 1;
      result.basis_at(point(s[0], s[1], s[2]), order, d_ids[a], d_values[a]);
    }
    double limit = options.max_support_steps, total = 0.0, movable = 0.0;
    for (;; limit *= 2) {
      total = movable = 0.0;
      for (std::size_t q = 0; q < d_ids[0].size(); ++q) {
        const int f = d_ids[0][q];
        const double g = w(f) * Eigen::Vector3d(d_values[0][q], d_values[1][q], d_values[2][q]).norm();
        total += g;
        if (support_steps(f) <= limit && !touches_domain_boundary(result.knots()[f], lo, hi)) movable += g;
      }
      if (movable >= kMinMovableShare * total || limit >= l) break;
    }
    for (int dk = -options.rings; dk <= options.rings; ++dk)
      for (int dj = -options.rings; dj <= options.rings; ++dj)
        for (int di = -options.rings; di <= options.rings; ++di) {
          const int i = s[0] + di, j = s[1] + dj, k = s[2] + dk;
          if (i < 0 || j < 0 || k < 0 || i >= m || j >= m || k >= m) continue;
          result.basis_at(point(i, j, k), {0, 0, 0}, ids, values);
          for (std::size_t q = 0; q < ids.size(); ++q) {
            const int f = ids[q];
            if (values[q] == 0.0 || column_of[f] >= 0 || touches_domain_boundary(result.knots()[f], lo, hi) ||
                support_steps(f) > limit)
              continue;
            column_of[f] = static_cast<int>(free_ids.size());
            free_ids.push_back(f);
          }
        }
  }
  report.free_functions = static_cast<int>(free_ids.size());
  if (free_ids.empty()) return report;
  std::sort(free_ids.begin(), free_ids.end());  // deterministic columns
  for (std::size_t c = 0; c < free_ids.size(); ++c) column_of[free_ids[c]] = static_cast<int>(c);

  // Energy points: every energy node in the support of a free function (so no point the
  // free functions change goes unseen), with the functions' factors of w·∇B on their boxes.
  Eigen::VectorXd x(3 * free_ids.size());
  for (std::size_t c = 0; c < free_ids.size(); ++c) x.segment<3>(3 * c) = current.row(free_ids[c]).transpose();
  const Eigen::VectorXd x0 = x;
  auto make_region = [&]() {
    std::vector<int> node_index(static_cast<std::size_t>(me) * me * me, -1);
    std::vector<FreeFunction> functions(free_ids.size());
    for (std::size_t c = 0; c < free_ids.size(); ++c) {
      const int f = free_ids[c];
      FreeFunction& ff = functions[c];
      for (int a = 0; a < 3; ++a) {
        const LocalKnots& r = result.knots()[f][a];
        const double t0 = (r[0] - lo(a)) / (hi(a) - lo(a)) * l, t1 = (r[4] - lo(a)) / (hi(a) - lo(a)) * l;
        // Lattice node i sits at t = i + 1: nodes first_node .. last_node are inside (t0, t1).
        const int first_node = std::max(0, static_cast<int>(std::floor(t0)));
        const int last_node = std::min(m - 1, static_cast<int>(std::ceil(t1)) - 2);
        const int first = (first_node + es - 1) / es, last = last_node >= 0 ? last_node / es : -1;
        ff.first[a] = first;
        ff.count[a] = std::max(0, last - first + 1);
        const double scale = a == 0 ? w(f) : 1.0;
        for (int i = 0; i < ff.count[a]; ++i) {
          const double t = lo(a) + (hi(a) - lo(a)) * ((first + i) * es + 1) / l;
          const BasisDerivatives d = cubic_basis_derivatives(r, t);
          ff.value[a].push_back(scale * d.value);
          ff.slope[a].push_back(scale * d.d1);
        }
      }
      for (int k = 0; k < ff.count[2]; ++k)
        for (int j = 0; j < ff.count[1]; ++j)
          for (int i = 0; i < ff.count[0]; ++i)
            node_index[ff.first[0] + i + me * (ff.first[1] + j + me * (ff.first[2] + k))] = 0;
    }
    Region region;
    std::vector<Eigen::Matrix3d> fixed;
    for (int k = 0; k < m; k += es)
      for (int j = 0; j < m; j += es)
        for (int i = 0; i < m; i += es) {
          int& id = node_index[index(i, j, k)];
          if (id < 0) continue;
          id = static_cast<int>(fixed.size());
          const Eigen::Matrix3d jac = jacobian_at(i, j, k);
          // Reference: the point's own Jacobian where it is good (the energy is then least where
          // the map already is), else an orthogonal frame of its column lengths.
          const Eigen::Vector3d norms(jac.col(0).norm(), jac.col(1).norm(), jac.col(2).norm());
          region.mean_scale += norms;
          region.inverse_reference.push_back(
              scaled_jacobian(jac) >= kGoodScaledJacobian
                  ? Eigen::Matrix3d(jac.inverse())
                  : Eigen::Matrix3d(norms.cwiseMax(1e-300).cwiseInverse().asDiagonal()));
          fixed.push_back(jac);
          const int ss = options.seed_stride;
          region.guarded.push_back(jac.determinant() > 0.0 || (i % ss == 0 && j % ss == 0 && k % ss == 0));
        }
    region.mean_scale /= std::max<std::size_t>(fixed.size(), 1);
    region.fixed = MatrixField(fixed.size());
    for (std::size_t q = 0; q < fixed.size(); ++q) region.fixed.set(q, fixed[q]);
    region.lattice = LatticeJacobians(std::move(functions), std::move(node_index), me);
    region.lattice.add(-x0, region.fixed);  // fixed: the part of J the free functions do not change
    return region;
  };
  const Region region = make_region();
  // One lattice step in model units: the length unit of the data term.
  const double step = (region.mean_scale.array() * (hi - lo).array()).mean() / l;

  std::vector<SampleTerm> samples;
  for (Eigen::Index s = 0; s < uvw.rows(); ++s) {
    result.basis_at(uvw.row(s).transpose(), {0, 0, 0}, ids, values);
    SampleTerm t;
    t.fixed.setZero();
    t.target = xyz.row(s).transpose();
    for (std::size_t q = 0; q < ids.size(); ++q) {
      const double b = w(ids[q]) * values[q];
      if (column_of[ids[q]] >= 0 && b != 0.0)
        t.entries.emplace_back(column_of[ids[q]], b);
      else
        t.fixed += b * current.row(ids[q]).transpose();
    }
    if (!t.entries.empty()) samples.push_back(std::move(t));
  }
  report.samples = static_cast<int>(samples.size());

  const double data_scale = options.data_weight / (step * step);
  const double theta = options.volume_weight;
  MatrixField jac, dj;
  // Minimizes the energy over the region's nodes: the barrier of Garanzha et al. 2021 (§3, with
  // its ε continuation; the thesis has no untangling step).
  auto solve = [&](const Region& r) {
    const std::size_t num_points = r.fixed.size();
    dj = MatrixField(num_points);
    // jac holds J at jac_x. J is linear in x: along the line search's line x + t·d it is
    // J(x) + t·J_d, so a trial needs no lattice sums.
    Eigen::VectorXd jac_x, line_x, line_d;
    MatrixField line_start, line_step;
    auto jacobians = [&](const Eigen::VectorXd& y) -> const MatrixField& {
      if (jac_x.size() != y.size() || jac_x != y) {
        jac = r.fixed;
        r.lattice.add(y, jac);
        jac_x = y;
      }
      return jac;
    };
    auto energy = [&](const MatrixField& j, const Eigen::VectorXd& y, double eps, Eigen::VectorXd* gradient) {
      double total = 0.0;
      Eigen::Matrix3d df;
      for (std::size_t q = 0; q < num_points; ++q) {
        total += param::foldover_free_energy(j.get(q) * r.inverse_reference[q], eps, theta, gradient ? &df : nullptr);
        if (gradient) dj.set(q, df * r.inverse_reference[q].transpose());  // ∂f/∂J
      }
      if (gradient) {
        gradient->setZero(y.size());
        r.lattice.add_gradient(dj, *gradient);
      }
      for (const SampleTerm& t : samples) {
        Eigen::Vector3d res = t.fixed - t.target;
        for (const auto& [e, b] : t.entries) res += b * y.segment<3>(3 * e);
        total += data_scale * res.squaredNorm();
        if (!gradient) continue;
        for (const auto& [e, b] : t.entries) gradient->segment<3>(3 * e) += 2.0 * data_scale * b * res;
      }
      return total;
    };
    param::UntangleProblem problem;
    problem.energy = [&](const Eigen::VectorXd& y, double eps, Eigen::VectorXd* gradient) {
      return energy(jacobians(y), y, eps, gradient);
    };
    problem.min_det = [&](const Eigen::VectorXd& y) {
      const MatrixField& j = jacobians(y);
      double worst = std::numeric_limits<double>::infinity();
      for (std::size_t q = 0; q < num_points; ++q)
        if (r.guarded[q]) worst = std::min(worst, (j.get(q) * r.inverse_reference[q]).determinant());
      return worst;
    };
    problem.set_line = [&](const Eigen::VectorXd& y, const Eigen::VectorXd& d) {
      line_start = jacobians(y);
      line_x = y;
      line_d = d;
      line_step = MatrixField(num_points);
      r.lattice.add(d, line_step);
    };
    problem.line_energy = [&](double t, double eps, Eigen::VectorXd* gradient) {
      jac_x = line_x + t * line_d;  // the same bits as the minimizer's x + t·d
      for (std::size_t e = 0; e < 9 * num_points; ++e) jac.data()[e] = line_start.data()[e] + t * line_step.data()[e];
      return energy(jac, jac_x, eps, gradient);
    };
    param::UntangleOptions untangle_options;
    untangle_options.max_steps = options.max_steps;
    untangle_options.max_inner = options.max_inner;
    untangle_options.stop_min_det = 0.0;
    untangle_options.keep_curvature = true;
    untangle_options.min_sigma = kMinSigma;
    return param::untangle(problem, x, untangle_options);
  };
  report.points = static_cast<int>(region.fixed.size());
  report.iterations = solve(region);

  for (std::size_t c = 0; c < free_ids.size(); ++c) current.row(free_ids[c]) = x.segment<3>(3 * c).transpose();
  if (correction.size() == 0) correction = MatrixField(static_cast<std::size_t>(me) * me * me);
  region.lattice.add(x - x0, correction, true);
  scan(nullptr);
  return report;
}

}  // namespace

SplineUntangleReport untangle_spline(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                                     const SplineUntangleOptions& options) {
  assert(spline.dimension() == 3 && uvw.rows() == xyz.rows());
  assert(options.lattice >= 4 && options.seed_stride >= 1 && options.rings >= 0 && options.max_support_steps >= 4);
  assert(options.passes >= 1);
  assert(options.energy_stride >= 1 && options.seed_stride % options.energy_stride == 0);
  SplineUntangleReport total;
  Eigen::MatrixXd current = spline.points();
  MatrixField correction;
  SplineUntangleOptions pass_options = options;
  for (int pass = 0; pass < options.passes; ++pass, pass_options.max_support_steps *= 2) {
    // Each pass lets coarser functions move: the few seeds the fine ones could not fix.
    const SplineUntangleReport r = untangle_pass(spline, current, correction, uvw, xyz, pass_options);
    if (pass == 0) {
      total.seeds = r.seeds;
      total.initial_negative = r.initial_negative;
    }
    total.scanned = r.scanned;
    total.final_negative = r.final_negative;
    total.final_min_scaled = r.final_min_scaled;
    total.free_functions += r.free_functions;
    total.points += r.points;
    total.samples += r.samples;
    total.iterations += r.iterations;
    if (r.seeds == 0 || r.final_negative == 0) break;
  }
  if (total.free_functions > 0) spline.set_points(std::move(current));
  return total;
}

}  // namespace volspline::spline
