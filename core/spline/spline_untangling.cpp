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
#include "core/spline/tspline_fitting.h"

namespace volspline::spline {

namespace {

// Points at least this good (scaled Jacobian) keep their own Jacobian as the rest shape.
constexpr double kGoodScaledJacobian = 0.1;

double scaled_jacobian(const Eigen::Matrix3d& j) {
  const double norms = j.col(0).norm() * j.col(1).norm() * j.col(2).norm();
  return norms > 0.0 ? j.determinant() / norms : -1.0;
}

// J(x) = fixed + Σ_e x_e g_eᵀ at one lattice point (x_e: control point of free function e).
struct PointTerm {
  Eigen::Matrix3d fixed;
  Eigen::Matrix3d inverse_reference;  // J·inverse_reference is the element Jacobian
  std::vector<std::pair<int, Eigen::Vector3d>> entries;
};

// F(x) = fixed + Σ_e x_e b_e at one sample, target xyz.
struct SampleTerm {
  Eigen::Vector3d fixed, target;
  std::vector<std::pair<int, double>> entries;
};

Eigen::Matrix3d point_jacobian(const PointTerm& t, const Eigen::VectorXd& x) {
  Eigen::Matrix3d j = t.fixed;
  for (const auto& [e, g] : t.entries) j += x.segment<3>(3 * e) * g.transpose();
  return j;
}

// One scan for seeds and one untangling of the points near them.
SplineUntangleReport untangle_pass(TSpline& result, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                                   const SplineUntangleOptions& options) {
  SplineUntangleReport report;
  const int l = options.lattice, m = l - 1;  // m lattice nodes per axis, index i ↔ (i + 1)/l
  const Eigen::Vector3d lo = result.domain_min(), hi = result.domain_max();
  auto point = [&](int i, int j, int k) {
    return Eigen::Vector3d(lo + (hi - lo).cwiseProduct(Eigen::Vector3d(i + 1, j + 1, k + 1) / l));
  };
  auto index = [&](int i, int j, int k) { return i + m * (j + m * k); };

  // The scanned points: counts of non-positive ones, the minimum, and the seeds (if asked).
  auto scan = [&](std::vector<std::array<int, 3>>* seeds) {
    double value[3];
    Eigen::Matrix3d jac;
    report.scanned = 0;
    report.final_negative = 0;
    report.final_min_scaled = 1.0;
    for (int k = 0; k < m; k += options.seed_stride)
      for (int j = 0; j < m; j += options.seed_stride)
        for (int i = 0; i < m; i += options.seed_stride) {
          result.evaluate_with_jacobian(point(i, j, k), TSplineForm::SemiStandard, value, jac.data());
          const double q = scaled_jacobian(jac);
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

  // Free functions: interior ones acting near a seed.
  const int n = result.num_functions();
  std::vector<int> column_of(n, -1), free_ids;
  std::vector<int> ids;
  std::vector<double> values;
  for (const auto& s : seeds)
    for (int dk = -options.rings; dk <= options.rings; ++dk)
      for (int dj = -options.rings; dj <= options.rings; ++dj)
        for (int di = -options.rings; di <= options.rings; ++di) {
          const int i = s[0] + di, j = s[1] + dj, k = s[2] + dk;
          if (i < 0 || j < 0 || k < 0 || i >= m || j >= m || k >= m) continue;
          result.basis_at(point(i, j, k), {0, 0, 0}, ids, values);
          for (std::size_t q = 0; q < ids.size(); ++q) {
            const int f = ids[q];
            if (values[q] == 0.0 || column_of[f] >= 0 || touches_domain_boundary(result.knots()[f], lo, hi)) continue;
            bool small = true;
            for (int a = 0; a < 3; ++a) {
              const LocalKnots& r = result.knots()[f][a];
              small = small && (r[4] - r[0]) / (hi(a) - lo(a)) * l <= options.max_support_steps;
            }
            if (!small) continue;
            column_of[f] = static_cast<int>(free_ids.size());
            free_ids.push_back(f);
          }
        }
  report.free_functions = static_cast<int>(free_ids.size());
  if (free_ids.empty()) return report;
  std::sort(free_ids.begin(), free_ids.end());  // deterministic columns
  for (std::size_t c = 0; c < free_ids.size(); ++c) column_of[free_ids[c]] = static_cast<int>(c);

  // Energy points: every lattice node in the support of a free function (so no point the
  // free functions change goes unseen).
  std::vector<char> in_region(static_cast<std::size_t>(m) * m * m, 0);
  for (int f : free_ids) {
    std::array<int, 3> first, last;
    for (int a = 0; a < 3; ++a) {
      const LocalKnots& r = result.knots()[f][a];
      const double t0 = (r[0] - lo(a)) / (hi(a) - lo(a)) * l, t1 = (r[4] - lo(a)) / (hi(a) - lo(a)) * l;
      first[a] = std::max(0, static_cast<int>(std::floor(t0)));  // node i sits at t = i + 1
      last[a] = std::min(m - 1, static_cast<int>(std::ceil(t1)) - 2);
    }
    for (int k = first[2]; k <= last[2]; ++k)
      for (int j = first[1]; j <= last[1]; ++j)
        for (int i = first[0]; i <= last[0]; ++i) in_region[index(i, j, k)] = 1;
  }
  const Eigen::VectorXd& w = result.weights();
  const Eigen::MatrixXd& p = result.points();
  std::vector<PointTerm> points;
  std::array<std::vector<int>, 3> d_ids;
  std::array<std::vector<double>, 3> d_values;
  Eigen::Vector3d mean_scale = Eigen::Vector3d::Zero();
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        if (!in_region[index(i, j, k)]) continue;
        const Eigen::Vector3d u = point(i, j, k);
        for (int a = 0; a < 3; ++a) {
          std::array<int, 3> order = {0, 0, 0};
          order[a] = 1;
          result.basis_at(u, order, d_ids[a], d_values[a]);
        }
        PointTerm t;
        t.fixed.setZero();
        for (std::size_t q = 0; q < d_ids[0].size(); ++q) {
          const int f = d_ids[0][q];
          const Eigen::Vector3d g = w(f) * Eigen::Vector3d(d_values[0][q], d_values[1][q], d_values[2][q]);
          t.fixed += p.row(f).transpose() * g.transpose();
          if (column_of[f] >= 0 && g.squaredNorm() > 0.0) t.entries.emplace_back(column_of[f], g);
        }
        // Reference: the point's own Jacobian where it is good (the energy is then least where
        // the map already is), else an orthogonal frame of its column lengths.
        const Eigen::Vector3d norms(t.fixed.col(0).norm(), t.fixed.col(1).norm(), t.fixed.col(2).norm());
        mean_scale += norms;
        t.inverse_reference = scaled_jacobian(t.fixed) >= kGoodScaledJacobian
                                  ? Eigen::Matrix3d(t.fixed.inverse())
                                  : Eigen::Matrix3d(norms.cwiseMax(1e-300).cwiseInverse().asDiagonal());
        for (const auto& [e, g] : t.entries) t.fixed -= p.row(free_ids[e]).transpose() * g.transpose();
        points.push_back(std::move(t));
      }
  report.points = static_cast<int>(points.size());
  mean_scale /= std::max<std::size_t>(points.size(), 1);
  // One lattice step in model units: the length unit of the data term.
  const double step = (mean_scale.array() * (hi - lo).array()).mean() / l;

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
        t.fixed += b * p.row(ids[q]).transpose();
    }
    if (!t.entries.empty()) samples.push_back(std::move(t));
  }
  report.samples = static_cast<int>(samples.size());

  const double data_scale = options.data_weight / (step * step);
  const double theta = options.volume_weight;
  param::UntangleProblem problem;
  problem.energy = [&](const Eigen::VectorXd& x, double eps, Eigen::VectorXd* gradient) {
    if (gradient) gradient->setZero(x.size());
    double total = 0.0;
    Eigen::Matrix3d df;
    for (const PointTerm& t : points) {
      const Eigen::Matrix3d j = point_jacobian(t, x) * t.inverse_reference;
      total += param::foldover_free_energy(j, eps, theta, gradient ? &df : nullptr);
      if (!gradient) continue;
      df = df * t.inverse_reference.transpose();  // ∂f/∂J of the spline's Jacobian
      for (const auto& [e, g] : t.entries) gradient->segment<3>(3 * e) += df * g;
    }
    for (const SampleTerm& t : samples) {
      Eigen::Vector3d r = t.fixed - t.target;
      for (const auto& [e, b] : t.entries) r += b * x.segment<3>(3 * e);
      total += data_scale * r.squaredNorm();
      if (!gradient) continue;
      for (const auto& [e, b] : t.entries) gradient->segment<3>(3 * e) += 2.0 * data_scale * b * r;
    }
    return total;
  };
  problem.min_det = [&](const Eigen::VectorXd& x) {
    double worst = std::numeric_limits<double>::infinity();
    for (const PointTerm& t : points) worst = std::min(worst, (point_jacobian(t, x) * t.inverse_reference).determinant());
    return worst;
  };
  Eigen::VectorXd x(3 * free_ids.size());
  for (std::size_t c = 0; c < free_ids.size(); ++c) x.segment<3>(3 * c) = p.row(free_ids[c]).transpose();
  param::UntangleOptions untangle_options;
  untangle_options.max_steps = options.max_steps;
  untangle_options.max_inner = options.max_inner;
  untangle_options.stop_min_det = 0.0;
  report.iterations = param::untangle(problem, x, untangle_options);

  Eigen::MatrixXd moved = p;
  for (std::size_t c = 0; c < free_ids.size(); ++c) moved.row(free_ids[c]) = x.segment<3>(3 * c).transpose();
  result.set_points(std::move(moved));
  scan(nullptr);
  return report;
}

}  // namespace

SplineUntangleReport untangle_spline(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                                     const SplineUntangleOptions& options) {
  assert(spline.dimension() == 3 && uvw.rows() == xyz.rows());
  assert(options.lattice >= 4 && options.seed_stride >= 1 && options.rings >= 0 && options.max_support_steps >= 4);
  assert(options.passes >= 1);
  SplineUntangleReport total;
  SplineUntangleOptions pass_options = options;
  for (int pass = 0; pass < options.passes; ++pass, pass_options.max_support_steps *= 2) {
    // Each pass lets coarser functions move: the few seeds the fine ones could not fix.
    const SplineUntangleReport r = untangle_pass(spline, uvw, xyz, pass_options);
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
  return total;
}

}  // namespace volspline::spline
