// SPDX-License-Identifier: MIT
#include "core/spline/untangle_energy.h"

#include <algorithm>
#include <cstddef>
#include <limits>

#include <Eigen/Geometry>

#include "core/param/barrier_untangling.h"

namespace volspline::spline::detail {

namespace {

// ε shrinks at least this much per step (param::UntangleOptions::min_sigma): 5 steps instead
// of 8 on bunny with 0.5; 0.9 shrinks it faster than the folds open.
constexpr double kMinSigma = 0.75;
// Weight of the scattered nodes' hinge (tuning, rings 1 in all passes): 100 left bunny 9 folded
// points of 64³, 1000 left 4, 10⁴ left 19 (it then outweighs the barrier that holds the nodes).
constexpr double kHingeWeight = 1000.0;

// The energy of minimize_region_energy with its caches. The energy's nodes are the held ones
// (guarded ⊆ held), kFoldoverBatch to a batch; M = J·S⁻¹ of a batch is stored as the batch
// kernel reads it (element k of lane l at 9·kBatch·b + k·kBatch + l), the last batch padded
// with its last node. M is linear in x: along the line search's line x + t·d it is M(x) + t·M_d,
// so a trial needs no sums over the functions.
class RegionEnergy {
 public:
  RegionEnergy(const Region& region, const SampleTerms& samples, const RegionEnergyOptions& options)
      : r_(region), samples_(samples), options_(options), num_extra_(region.point_fixed.size()),
        extra_jac_(num_extra_), extra_start_(num_extra_), extra_step_(num_extra_) {
    for (std::size_t q = 0; q < r_.fixed.size(); ++q)
      if (r_.held[q]) held_nodes_.push_back(static_cast<int>(q));
    num_batches_ = (held_nodes_.size() + kBatch - 1) / kBatch;
    lanes_ = num_batches_ * kBatch;
  }

  double energy(const Eigen::VectorXd& y, double eps, Eigen::VectorXd* gradient) {
    return sum(jacobians(y).data(), nullptr, 0.0, y, eps, gradient);
  }

  double min_det(const Eigen::VectorXd& y) {
    const std::vector<double>& j = jacobians(y);
    double worst = std::numeric_limits<double>::infinity();
    for (std::size_t h = 0; h < held_nodes_.size(); ++h)
      if (r_.guarded[held_nodes_[h]]) worst = std::min(worst, get(j, h).determinant());
    return worst;
  }

  void set_line(const Eigen::VectorXd& y, const Eigen::VectorXd& d) {
    if (on_line_ && jac_x_ == y) {
      // The step taken on the last line: M there is start + t·step, formed in place.
      for (std::size_t i = 0; i < line_start_.size(); ++i) line_start_[i] += line_t_ * line_step_[i];
    } else {
      line_start_ = jacobians(y);
    }
    // jac_ is not kept in step with the line: M at jac_x_ is start + t·step until jacobians() forms it.
    jac_x_ = y;
    on_line_ = true;
    line_t_ = 0.0;
    line_x_ = y;
    line_d_ = d;
    fill(line_step_, d, Part::Linear);
    for (std::size_t e = 0; e < num_extra_; ++e) {
      extra_start_[e] = extra_jac_[e];
      extra_step_[e] = extra_linear(e);
    }
  }

  // M at x + t·d is start + t·step, formed batch by batch as the barrier reads it.
  double line_energy(double t, double eps, Eigen::VectorXd* gradient) {
    jac_x_ = line_x_ + t * line_d_;  // the same bits as the minimizer's x + t·d
    on_line_ = true;
    line_t_ = t;
    for (std::size_t e = 0; e < num_extra_; ++e) extra_jac_[e] = extra_start_[e] + t * extra_step_[e];
    return sum(line_start_.data(), line_step_.data(), t, jac_x_, eps, gradient);
  }

 private:
  static constexpr int kBatch = param::kFoldoverBatch;
  enum class Part { WithFixed, Linear };  // fixed + rows(y), or rows(y) alone

  static void put(std::vector<double>& m, std::size_t h, const Eigen::Matrix3d& value) {
    double* out = m.data() + (h / kBatch) * 9 * kBatch + h % kBatch;
    for (int k = 0; k < 9; ++k) out[k * kBatch] = value.data()[k];
  }
  static Eigen::Matrix3d get(const std::vector<double>& m, std::size_t h) {
    const double* in = m.data() + (h / kBatch) * 9 * kBatch + h % kBatch;
    Eigen::Matrix3d value;
    for (int k = 0; k < 9; ++k) value.data()[k] = in[k * kBatch];
    return value;
  }

  // M at every held node from the rows.
  void fill(std::vector<double>& m, const Eigen::VectorXd& y, Part part) {
    m.resize(9 * lanes_);
    NodeJacobians::pad(y, padded_);
    for (std::size_t h = 0; h < lanes_; ++h) {
      const int q = held_nodes_[std::min(h, held_nodes_.size() - 1)];
      const Eigen::Matrix3d linear = r_.rows.linear(padded_.data(), q);
      put(m, h, part == Part::WithFixed ? Eigen::Matrix3d(r_.fixed[q] + linear) : linear);
    }
  }

  // Σ y_c·g_cᵀ at scattered node e, y padded in padded_ (the vector fill was last given).
  Eigen::Matrix3d extra_linear(std::size_t e) const {
    return scattered_linear(r_.point_columns.data(), r_.point_g.empty() ? nullptr : r_.point_g.front().data(),
                            r_.point_start[e], r_.point_start[e + 1], padded_.data());
  }

  // M at y: jac_ (formed from the line if jac_x_ = y lies on it).
  const std::vector<double>& jacobians(const Eigen::VectorXd& y) {
    if (jac_x_.size() != y.size() || jac_x_ != y) {
      fill(jac_, y, Part::WithFixed);
      for (std::size_t e = 0; e < num_extra_; ++e) extra_jac_[e] = r_.point_fixed[e] + extra_linear(e);
      jac_x_ = y;
    } else if (on_line_) {
      jac_.resize(line_start_.size());
      for (std::size_t i = 0; i < jac_.size(); ++i) jac_[i] = line_start_[i] + line_t_ * line_step_[i];
    }
    on_line_ = false;
    return jac_;
  }

  // The three terms, added to total in this order (barrier, hinge, data). M at the held nodes:
  // start, or start + t·step if step is given.
  double sum(const double* start, const double* step, double t, const Eigen::VectorXd& y, double eps,
             Eigen::VectorXd* gradient) {
    double total = 0.0;
    add_barrier(start, step, t, eps, y.size(), total, gradient);
    add_hinge(total, gradient);
    add_data(y, total, gradient);
    return total;
  }

  // The barrier at the held nodes, summed and its gradient scattered in node order (as one at a
  // time); sets the gradient whole.
  void add_barrier(const double* start, const double* step, double t, double eps, Eigen::Index size, double& total,
                   Eigen::VectorXd* gradient) {
    if (gradient) {
      gradient->resize(size);  // set whole from gradient_padded_ below
      gradient_padded_.assign(size / 3 * 4, 0.0);
    }
    double out[9 * kBatch], e[kBatch], m[9 * kBatch];
    for (std::size_t batch = 0; batch < num_batches_; ++batch) {
      const std::size_t first = batch * kBatch;
      const int count = static_cast<int>(std::min<std::size_t>(kBatch, held_nodes_.size() - first));
      const double* j = start + batch * 9 * kBatch;
      if (step) {
        const double* s = step + batch * 9 * kBatch;
        for (int k = 0; k < 9 * kBatch; ++k) m[k] = j[k] + t * s[k];
        j = m;
      }
      param::foldover_free_energy_batch(j, eps, options_.theta, e, gradient ? out : nullptr);
      for (int lane = 0; lane < count; ++lane) {
        total += e[lane];
        if (!gradient) continue;
        Eigen::Matrix3d df;
        for (int k = 0; k < 9; ++k) df.data()[k] = out[k * kBatch + lane];
        r_.rows.add_gradient(df, held_nodes_[first + lane], gradient_padded_.data());
      }
    }
    if (gradient) NodeJacobians::unpad(gradient_padded_, *gradient);
  }

  // Scattered nodes: the hinge W·max(0, τ − det J/σ)², zero where they are good enough.
  void add_hinge(double& total, Eigen::VectorXd* gradient) const {
    for (std::size_t e = 0; e < num_extra_; ++e) {
      const Eigen::Matrix3d& m = extra_jac_[e];
      const double target = r_.point_target.empty() ? options_.hinge_target : r_.point_target[e];
      const double gap = target - m.determinant() / r_.point_scale[e];
      if (gap <= 0.0) continue;
      const double weight = r_.point_weight.empty() ? kHingeWeight : kHingeWeight * r_.point_weight[e];
      total += weight * gap * gap;
      if (!gradient) continue;
      Eigen::Matrix3d cof;  // ∂det/∂J
      cof.col(0) = m.col(1).cross(m.col(2));
      cof.col(1) = m.col(2).cross(m.col(0));
      cof.col(2) = m.col(0).cross(m.col(1));
      const Eigen::Matrix3d d = (-2.0 * weight * gap / r_.point_scale[e]) * cof;
      for (int k = r_.point_start[e]; k < r_.point_start[e + 1]; ++k)
        gradient->segment<3>(3 * r_.point_columns[k]) += d * r_.point_g[k];
    }
  }

  // The samples' term data_scale·‖F(uvw_s) − xyz_s‖²; with a normal n, (n·r)² + t·(‖r‖² − (n·r)²)
  // (t: tangent_weight), so a surface sample may slide along the surface.
  void add_data(const Eigen::VectorXd& y, double& total, Eigen::VectorXd* gradient) const {
    const double data_scale = options_.data_scale;
    const double t_weight = options_.tangent_weight;
    const bool normals = !samples_.normal.empty();
    for (int t = 0; t < samples_.size(); ++t) {
      Eigen::Vector3d res = samples_.offset[t];
      for (int k = samples_.start[t]; k < samples_.start[t + 1]; ++k)
        res += samples_.b[k] * y.segment<3>(3 * samples_.column[k]);
      Eigen::Vector3d pull = res;  // half the gradient of the term with respect to F
      if (normals && samples_.normal[t] != Eigen::Vector3d::Zero()) {
        const Eigen::Vector3d& n = samples_.normal[t];
        const double along = n.dot(res);
        total += data_scale * (along * along + t_weight * (res.squaredNorm() - along * along));
        pull = t_weight * res + (1.0 - t_weight) * along * n;
      } else {
        total += data_scale * res.squaredNorm();
      }
      if (!gradient) continue;
      for (int k = samples_.start[t]; k < samples_.start[t + 1]; ++k)
        gradient->segment<3>(3 * samples_.column[k]) += 2.0 * data_scale * samples_.b[k] * pull;
    }
  }

  const Region& r_;
  const SampleTerms& samples_;
  const RegionEnergyOptions options_;
  std::vector<int> held_nodes_;
  std::size_t num_batches_ = 0, lanes_ = 0;
  std::vector<double> padded_, gradient_padded_;
  std::vector<double> jac_, line_start_, line_step_;
  Eigen::VectorXd jac_x_, line_x_, line_d_;
  bool on_line_ = false;  // M at jac_x_ is line_start_ + line_t_·line_step_, jac_ not formed
  double line_t_ = 0.0;
  const std::size_t num_extra_;
  std::vector<Eigen::Matrix3d> extra_jac_, extra_start_, extra_step_;
};

}  // namespace

int minimize_region_energy(const Region& region, const SampleTerms& samples, const RegionEnergyOptions& options,
                           Eigen::VectorXd& x) {
  RegionEnergy energy(region, samples, options);
  param::UntangleProblem problem;
  problem.energy = [&](const Eigen::VectorXd& y, double eps, Eigen::VectorXd* gradient) {
    return energy.energy(y, eps, gradient);
  };
  problem.min_det = [&](const Eigen::VectorXd& y) { return energy.min_det(y); };
  problem.set_line = [&](const Eigen::VectorXd& y, const Eigen::VectorXd& d) { energy.set_line(y, d); };
  problem.line_energy = [&](double t, double eps, Eigen::VectorXd* gradient) {
    return energy.line_energy(t, eps, gradient);
  };
  param::UntangleOptions untangle_options;
  untangle_options.max_steps = options.max_steps;
  untangle_options.max_inner = options.max_inner;
  untangle_options.stop_min_det = options.stop_margin;
  untangle_options.keep_curvature = param::UntangleOptions::KeepCurvature::On;
  untangle_options.min_sigma = kMinSigma;
  return param::untangle(problem, x, untangle_options);
}

}  // namespace volspline::spline::detail
