// SPDX-License-Identifier: MIT
#include "core/spline/untangle_pass.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/LU>

#include "core/mesh/hex_quality.h"
#include "core/spline/bezier_extraction.h"
#include "core/spline/bspline_basis.h"
#include "core/spline/node_jacobians.h"
#include "core/spline/tspline_fitting.h"
#include "core/spline/untangle_energy.h"

namespace volspline::spline::detail {

namespace {

// Points at least this good (scaled Jacobian) keep their own Jacobian as the rest shape.
constexpr double kGoodScaledJacobian = 0.1;

using NodeId = std::array<int, 3>;

bool same_nodes(const std::array<AxisNodes, 3>& a, const std::array<AxisNodes, 3>& b) {
  for (int k = 0; k < 3; ++k)
    if (a[k].t != b[k].t || a[k].scanned != b[k].scanned) return false;
  return true;
}

// One pass of untangle_pass. The steps, in run's order: node Jacobians (from the cache when
// the last pass left them), the scan for seeds, the free functions near the seeds, the region
// of energy nodes in their supports with the rows of their Jacobians, the samples' terms, the
// minimization, and the write-back (with a scan of the moved spline).
class UntanglePass {
 public:
  UntanglePass(TSpline& spline, const std::array<AxisNodes, 3>& nodes, const SplineUntangleOptions& options,
               NodeCache& cache)
      : spline_(spline), nodes_(nodes), options_(options), cache_(cache), lo_(region_min(spline, options)),
        hi_(region_max(spline, options)),
        sizes_{static_cast<int>(nodes[0].t.size()), static_cast<int>(nodes[1].t.size()),
               static_cast<int>(nodes[2].t.size())},
        box_lo_{0, 0, 0}, box_hi_(sizes_) {}

  SplineUntangleResult run(const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                           const std::vector<Eigen::Vector3d>& points, PassSeeds seed_kind,
                           const std::vector<Eigen::Vector3d>& held, double tangent_weight) {
    const bool from_scan = seed_kind == PassSeeds::ScanAndPoints;
    prepare_node_jacobians(from_scan);
    std::vector<NodeId> seeds;
    if (from_scan) {
      scan(&seeds);
      result_.seeds = static_cast<int>(seeds.size());
      result_.initial_negative = result_.final_negative;
    }
    add_nearest_nodes(points, seeds);
    if (seeds.empty()) return result_;

    select_free_functions(seeds);
    result_.free_functions = static_cast<int>(free_ids_.size());
    if (free_ids_.empty()) return result_;
    if (!from_scan) {
      shrink_box_to_supports();
      evaluate_nodes();
    }

    Eigen::MatrixXd current = spline_.points();
    Eigen::VectorXd x(3 * free_ids_.size());
    for (std::size_t c = 0; c < free_ids_.size(); ++c) x.segment<3>(3 * c) = current.row(free_ids_[c]).transpose();
    std::vector<Eigen::Vector3d> hinged = points;
    hinged.insert(hinged.end(), held.begin(), held.end());
    const Region region = make_region(x, hinged);
    // One lattice step in model units: the length unit of the data term.
    const double step = (region.mean_scale.array() * (hi_ - lo_).array()).mean() / options_.lattice;
    SampleTerms samples = make_samples(uvw, xyz, current);
    if (tangent_weight < 1.0) add_surface_normals(uvw, samples);
    result_.samples = samples.size();

    const RegionEnergyOptions energy_options = region_energy_options(options_, step, tangent_weight);
    result_.points = static_cast<int>(region.fixed.size());
    result_.iterations = minimize_region_energy(region, samples, energy_options, x);

    for (std::size_t c = 0; c < free_ids_.size(); ++c) current.row(free_ids_[c]) = x.segment<3>(3 * c).transpose();
    spline_.set_points(std::move(current));
    cache_.current = false;
    if (!from_scan) return result_;  // the polish scans its whole lattice itself
    evaluate_nodes();
    cache_.current = true;
    scan(nullptr);
    return result_;
  }

 private:
  Eigen::Vector3d point(int i, int j, int k) const {
    return Eigen::Vector3d(nodes_[0].t[i], nodes_[1].t[j], nodes_[2].t[k]);
  }
  int index(int i, int j, int k) const { return i + sizes_[0] * (j + sizes_[1] * k); }
  std::size_t num_nodes() const { return static_cast<std::size_t>(sizes_[0]) * sizes_[1] * sizes_[2]; }
  bool on_edge(int i, int j, int k) const {
    const int idx[3] = {i, j, k};
    int faces = 0;
    for (int a = 0; a < 3; ++a) faces += nodes_[a].t[idx[a]] == lo_(a) || nodes_[a].t[idx[a]] == hi_(a);
    return faces >= 2;
  }
  bool is_scanned(int i, int j, int k) const {
    return nodes_[0].scanned[i] && nodes_[1].scanned[j] && nodes_[2].scanned[k] && !on_edge(i, j, k);
  }
  const Eigen::Matrix3d& jacobian_at(int i, int j, int k) const { return cache_.jacobians[index(i, j, k)]; }
  bool touches_exposed_face(int f) const {
    return held_function(spline_.knots()[f], lo_, hi_, options_);
  }
  // Support of function f in lattice steps: the widest over the axes.
  double support_steps(int f) const {
    double steps = 0.0;
    for (int a = 0; a < 3; ++a) {
      const LocalKnots& r = spline_.knots()[f][a];
      steps = std::max(steps, (r[4] - r[0]) / (hi_(a) - lo_(a)) * options_.lattice);
    }
    return steps;
  }

  // J at every node of the box, one tensor-product pass per knot-line cell.
  void evaluate_nodes() {
    std::array<std::vector<double>, 3> coords;
    for (int a = 0; a < 3; ++a) coords[a].assign(nodes_[a].t.begin() + box_lo_[a], nodes_[a].t.begin() + box_hi_[a]);
    spline_.evaluate_lattice_with_jacobian(coords, [&](int i, int j, int k, const double*, const double* jacobian) {
      cache_.jacobians[index(i + box_lo_[0], j + box_lo_[1], k + box_lo_[2])] = Eigen::Map<const Eigen::Matrix3d>(jacobian);
    });
  }

  // A scanning pass reuses the cache's Jacobians when they are current for these nodes.
  void prepare_node_jacobians(bool from_scan) {
    const bool cached = from_scan && cache_.current && same_nodes(cache_.nodes, nodes_);
    cache_.current = false;
    cache_.jacobians.resize(num_nodes());
    if (!from_scan) return;
    if (!cached) evaluate_nodes();
    cache_.nodes = nodes_;
    cache_.current = true;  // until the pass moves control points
  }

  // The scanned nodes of the box: counts of non-positive ones, the minimum, and the seeds (if asked).
  void scan(std::vector<NodeId>* seeds) {
    result_.scanned = 0;
    result_.final_negative = 0;
    result_.final_min_scaled = 1.0;
    for (int k = box_lo_[2]; k < box_hi_[2]; ++k)
      for (int j = box_lo_[1]; j < box_hi_[1]; ++j)
        for (int i = box_lo_[0]; i < box_hi_[0]; ++i) {
          if (!is_scanned(i, j, k)) continue;
          const double q = mesh::scaled_jacobian(jacobian_at(i, j, k));
          ++result_.scanned;
          if (q <= 0.0) ++result_.final_negative;
          if (seeds && q < options_.min_scaled_jacobian) seeds->push_back({i, j, k});
          result_.final_min_scaled = std::min(result_.final_min_scaled, q);
        }
  }

  // A given point seeds at its nearest node; seeds sorted, without repeats.
  void add_nearest_nodes(const std::vector<Eigen::Vector3d>& points, std::vector<NodeId>& seeds) const {
    for (const Eigen::Vector3d& p : points) {
      NodeId s{};
      for (int a = 0; a < 3; ++a) {
        const std::vector<double>& t = nodes_[a].t;
        int i = static_cast<int>(std::lower_bound(t.begin(), t.end(), p(a)) - t.begin());
        if (i == static_cast<int>(t.size()) || (i > 0 && p(a) - t[i - 1] < t[i] - p(a))) --i;
        s[a] = i;
      }
      seeds.push_back(s);
    }
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  }

  // The support limit at a seed: max_support_steps, doubled while the interior functions within
  // it carry less than kMinMovableShare of the gradient there (the seed lies under boundary
  // functions and coarse ones, which small ones cannot unfold), at most the lattice.
  double support_limit(const NodeId& s, PointGradients& gradients) const {
    gradients.at(spline_, point(s[0], s[1], s[2]));
    double limit = options_.max_support_steps;
    for (;; limit *= 2) {
      double total = 0.0;
      const double movable = gradients.movable_share(
          spline_, [&](int f) { return support_steps(f) <= limit && !touches_exposed_face(f); }, &total);
      if (movable >= kMinMovableShare * total || limit >= options_.lattice) break;
    }
    return limit;
  }

  // Free functions: the interior ones non-zero within `rings` node steps of a seed, with supports
  // of at most the seed's limit; columns in function order (deterministic).
  void select_free_functions(const std::vector<NodeId>& seeds) {
    column_of_.assign(spline_.num_functions(), -1);
    PointGradients gradients;
    std::vector<int> ids;
    std::vector<double> values;
    std::vector<double> visited_limit(num_nodes(), 0.0);
    const int rings = options_.rings;
    for (const NodeId& s : seeds) {
      const double limit = support_limit(s, gradients);
      for (int dk = -rings; dk <= rings; ++dk)
        for (int dj = -rings; dj <= rings; ++dj)
          for (int di = -rings; di <= rings; ++di) {
            const int i = s[0] + di, j = s[1] + dj, k = s[2] + dk;
            if (i < 0 || j < 0 || k < 0 || i >= sizes_[0] || j >= sizes_[1] || k >= sizes_[2]) continue;
            // A node visited with a limit at least as large added every function this visit would.
            double& visited = visited_limit[index(i, j, k)];
            if (visited >= limit) continue;
            visited = limit;
            spline_.basis_at(point(i, j, k), {0, 0, 0}, ids, values);
            for (std::size_t q = 0; q < ids.size(); ++q) {
              const int f = ids[q];
              if (values[q] == 0.0 || column_of_[f] >= 0 || touches_exposed_face(f) || support_steps(f) > limit) continue;
              column_of_[f] = static_cast<int>(free_ids_.size());
              free_ids_.push_back(f);
            }
          }
    }
    std::sort(free_ids_.begin(), free_ids_.end());
    for (std::size_t c = 0; c < free_ids_.size(); ++c) column_of_[free_ids_[c]] = static_cast<int>(c);
  }

  // The nodes in the closed supports of the free functions (a seeds-from-points pass evaluates
  // and scans only those).
  void shrink_box_to_supports() {
    box_lo_ = sizes_;
    box_hi_ = {0, 0, 0};
    for (int f : free_ids_)
      for (int a = 0; a < 3; ++a) {
        const LocalKnots& r = spline_.knots()[f][a];
        const std::vector<double>& t = nodes_[a].t;
        box_lo_[a] = std::min(box_lo_[a], static_cast<int>(std::lower_bound(t.begin(), t.end(), r[0]) - t.begin()));
        box_hi_[a] = std::max(box_hi_[a], static_cast<int>(std::upper_bound(t.begin(), t.end(), r[4]) - t.begin()));
      }
    for (int a = 0; a < 3; ++a) box_hi_[a] = std::max(box_hi_[a], box_lo_[a]);
  }

  // Each free function's node box and factors of w·∇B there; marks its nodes in node_index (0).
  std::vector<FreeFunction> free_function_boxes(std::vector<int>& node_index) const {
    const Eigen::VectorXd& w = spline_.weights();
    std::vector<FreeFunction> functions(free_ids_.size());
    for (std::size_t c = 0; c < free_ids_.size(); ++c) {
      const int f = free_ids_[c];
      FreeFunction& ff = functions[c];
      for (int a = 0; a < 3; ++a) {
        const LocalKnots& r = spline_.knots()[f][a];
        // The nodes in the closed support [r0, r4] (the ends add zeros at most).
        const std::vector<double>& t = nodes_[a].t;
        const int first = static_cast<int>(std::lower_bound(t.begin(), t.end(), r[0]) - t.begin());
        const int end = static_cast<int>(std::upper_bound(t.begin(), t.end(), r[4]) - t.begin());
        ff.first[a] = first;
        ff.count[a] = std::max(0, end - first);
        const double scale = a == 0 ? w(f) : 1.0;
        const RightEnd right = r[4] == hi_(a) ? RightEnd::Closed : RightEnd::Open;  // nodes on the face
        for (int i = 0; i < ff.count[a]; ++i) {
          const BasisDerivatives d = cubic_basis_derivatives(r, t[first + i], right);
          ff.value[a].push_back(scale * d.value);
          ff.slope[a].push_back(scale * d.d1);
        }
      }
      for (int k = 0; k < ff.count[2]; ++k)
        for (int j = 0; j < ff.count[1]; ++j)
          for (int i = 0; i < ff.count[0]; ++i) node_index[index(ff.first[0] + i, ff.first[1] + j, ff.first[2] + k)] = 0;
    }
    return functions;
  }

  // Energy nodes: every node in the support of a free function (so no point the free functions
  // change goes unseen), numbered in lattice order; their J, held/guarded flags and reference
  // shapes. Returns J at each.
  std::vector<Eigen::Matrix3d> add_region_nodes(std::vector<int>& node_index, Region& region) const {
    std::vector<Eigen::Matrix3d> fixed;
    for (int k = 0; k < sizes_[2]; ++k)
      for (int j = 0; j < sizes_[1]; ++j)
        for (int i = 0; i < sizes_[0]; ++i) {
          int& id = node_index[index(i, j, k)];
          if (id < 0) continue;
          id = static_cast<int>(fixed.size());
          const Eigen::Matrix3d jac = jacobian_at(i, j, k);
          region.mean_scale += Eigen::Vector3d(jac.col(0).norm(), jac.col(1).norm(), jac.col(2).norm());
          fixed.push_back(jac);
          const bool held = !on_edge(i, j, k);
          region.held.push_back(held);
          region.guarded.push_back(held && (jac.determinant() > 0.0 || is_scanned(i, j, k)));
        }
    region.mean_scale /= std::max<std::size_t>(fixed.size(), 1);
    for (const Eigen::Matrix3d& jac : fixed) region.inverse_reference.push_back(inverse_reference_shape(jac, region.mean_scale));
    return fixed;
  }

  // The scattered nodes: at each given point, J without the free functions' part and their
  // w∇B there (points no free function reaches are left out).
  void add_scattered_nodes(const std::vector<Eigen::Vector3d>& points, const Eigen::VectorXd& x0, Region& region) const {
    const Eigen::VectorXd& w = spline_.weights();
    PointGradients gradients;
    for (const Eigen::Vector3d& p : points) {
      Eigen::Matrix3d jac;
      double value[3];
      spline_.evaluate_with_jacobian(p, TSplineForm::SemiStandard, value, jac.data());
      std::vector<std::pair<int, Eigen::Vector3d>> entries;
      gradients.at(spline_, p);
      const std::array<std::vector<double>, 3>& d = gradients.values;
      for (std::size_t q = 0; q < gradients.ids[0].size(); ++q) {
        const int c = column_of_[gradients.ids[0][q]];
        if (c < 0) continue;
        const Eigen::Vector3d g = w(gradients.ids[0][q]) * Eigen::Vector3d(d[0][q], d[1][q], d[2][q]);
        jac -= x0.segment<3>(3 * c) * g.transpose();
        entries.emplace_back(c, g);
      }
      if (entries.empty()) continue;
      Eigen::Matrix3d moved = Eigen::Matrix3d::Zero();
      for (const auto& [c, g] : entries) moved += x0.segment<3>(3 * c) * g.transpose();
      const Eigen::Matrix3d full = jac + moved;
      region.point_scale.push_back(std::max(full.col(0).norm() * full.col(1).norm() * full.col(2).norm(), 1e-300));
      region.point_fixed.push_back(jac);
      for (const auto& [c, g] : entries) {
        region.point_columns.push_back(c);
        region.point_g.push_back(g);
      }
      region.point_start.push_back(static_cast<int>(region.point_columns.size()));
    }
  }

  // The region of the pass at the free control points x0. The rows and fixed parts carry S⁻¹,
  // so the energy's sweeps need no 3×3 products: fixed is the part of J·S⁻¹ the free functions
  // do not change.
  Region make_region(const Eigen::VectorXd& x0, const std::vector<Eigen::Vector3d>& points) const {
    std::vector<double> x0_padded;
    NodeJacobians::pad(x0, x0_padded);
    std::vector<int> node_index(num_nodes(), -1);
    const std::vector<FreeFunction> functions = free_function_boxes(node_index);
    Region region;
    std::vector<Eigen::Matrix3d> fixed = add_region_nodes(node_index, region);
    add_scattered_nodes(points, x0, region);
    region.rows = NodeJacobians(functions, node_index, sizes_, fixed.size());
    for (std::size_t q = 0; q < fixed.size(); ++q) {
      region.rows.transform(q, region.inverse_reference[q]);
      fixed[q] = fixed[q] * region.inverse_reference[q] - region.rows.linear(x0_padded.data(), q);
    }
    region.fixed = std::move(fixed);
    return region;
  }

  // The samples' terms over the free functions; samples in a cell without free functions have
  // none (known per cell, without the basis).
  SampleTerms make_samples(const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz, const Eigen::MatrixXd& current) {
    const Eigen::VectorXd& w = spline_.weights();
    SampleTerms samples;
    std::vector<int> ids;
    std::vector<double> values;
    std::vector<signed char> cell_has_free(static_cast<std::size_t>(spline_.num_cells()), -1);
    for (Eigen::Index s = 0; s < uvw.rows(); ++s) {
      const int cell = spline_.cell_of(uvw.row(s).transpose());
      signed char& has_free = cell_has_free[static_cast<std::size_t>(cell)];
      if (has_free < 0) {
        spline_.cell_functions(cell, ids);
        has_free = std::any_of(ids.begin(), ids.end(), [&](int f) { return column_of_[f] >= 0; });
      }
      if (!has_free) continue;
      spline_.basis_at(uvw.row(s).transpose(), {0, 0, 0}, ids, values);
      Eigen::Vector3d fixed = Eigen::Vector3d::Zero();
      const std::size_t first = samples.column.size();
      for (std::size_t q = 0; q < ids.size(); ++q) {
        const double b = w(ids[q]) * values[q];
        if (column_of_[ids[q]] >= 0 && b != 0.0) {
          samples.column.push_back(column_of_[ids[q]]);
          samples.b.push_back(b);
        } else {
          fixed += b * current.row(ids[q]).transpose();
        }
      }
      if (samples.column.size() == first) continue;
      samples.offset.push_back(fixed - xyz.row(s).transpose());
      sample_rows_.push_back(static_cast<int>(s));
      samples.start.push_back(static_cast<int>(samples.column.size()));
    }
    return samples;
  }

  // Unit normals of the samples on a domain face: the cross product of the spline's two tangents
  // there; where they are within kMinTangentSine of parallel (a folded face parameterization),
  // the normal derivative's direction instead, which still crosses the surface.
  void add_surface_normals(const Eigen::MatrixX3d& uvw, SampleTerms& samples) const {
    constexpr double kMinTangentSine = 0.1;
    samples.normal.assign(samples.size(), Eigen::Vector3d::Zero());
    for (std::size_t t = 0; t < sample_rows_.size(); ++t) {
      const Eigen::Vector3d p = uvw.row(sample_rows_[t]).transpose();
      int face_axis = -1;
      for (int a = 0; a < 3; ++a)
        if (p(a) == lo_(a) || p(a) == hi_(a)) face_axis = a;
      if (face_axis < 0) continue;
      Eigen::Matrix3d jac;
      double value[3];
      spline_.evaluate_with_jacobian(p, TSplineForm::SemiStandard, value, jac.data());
      const Eigen::Vector3d t1 = jac.col((face_axis + 1) % 3), t2 = jac.col((face_axis + 2) % 3);
      const Eigen::Vector3d n = t1.cross(t2);
      const Eigen::Vector3d across = jac.col(face_axis);
      if (n.norm() >= kMinTangentSine * t1.norm() * t2.norm() && n.norm() > 0.0)
        samples.normal[t] = n.normalized();
      else if (across.norm() > 0.0)
        samples.normal[t] = across.normalized();
    }
  }

  TSpline& spline_;
  const std::array<AxisNodes, 3>& nodes_;
  const SplineUntangleOptions& options_;
  NodeCache& cache_;
  const Eigen::Vector3d lo_, hi_;
  const std::array<int, 3> sizes_;
  // Nodes box_lo_ .. box_hi_ − 1 per axis are evaluated and scanned: all of them, or (seeds
  // from points only) the box of the free functions' supports.
  std::array<int, 3> box_lo_, box_hi_;
  std::vector<int> column_of_, free_ids_;  // function → column (−1: fixed); column → function
  std::vector<int> sample_rows_;             // the uvw row of each sample term
  SplineUntangleResult result_;
};

}  // namespace

void PointGradients::at(const TSpline& spline, const Eigen::Vector3d& p) {
  spline.basis_gradient_at(p, ids[0], values);
  ids[1] = ids[0];
  ids[2] = ids[0];
}

bool CertificateRounds::stop(int round, int uncertified, const Eigen::MatrixXd& points, int max_rounds) {
  if (uncertified < best_) {
    best_ = uncertified;
    best_points_ = points;
    stalled_ = 0;
  } else {
    ++stalled_;
  }
  return uncertified == 0 || round == max_rounds || stalled_ > kPatience;
}

RegionEnergyOptions region_energy_options(const SplineUntangleOptions& options, double step, double tangent_weight) {
  RegionEnergyOptions out;
  out.data_scale = options.data_weight / (step * step);
  out.theta = options.volume_weight;
  out.hinge_target = options.min_scaled_jacobian;
  out.max_steps = options.max_steps;
  out.max_inner = options.max_inner;
  out.stop_margin = options.stop_margin;
  out.tangent_weight = tangent_weight;
  return out;
}

Eigen::Matrix3d inverse_reference_shape(const Eigen::Matrix3d& jacobian, const Eigen::Vector3d& mean_scale) {
  if (mesh::scaled_jacobian(jacobian) >= kGoodScaledJacobian) return jacobian.inverse();
  const Eigen::Vector3d norms(jacobian.col(0).norm(), jacobian.col(1).norm(), jacobian.col(2).norm());
  return norms.cwiseMax(mean_scale).cwiseMax(1e-300).cwiseInverse().asDiagonal();
}

bool lexicographic_less(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
}

void merge_points(std::vector<Eigen::Vector3d>& held, std::vector<Eigen::Vector3d> more) {
  std::sort(more.begin(), more.end(), lexicographic_less);
  const std::size_t before = held.size();
  held.insert(held.end(), more.begin(), more.end());
  std::inplace_merge(held.begin(), held.begin() + before, held.end(), lexicographic_less);
  held.erase(std::unique(held.begin(), held.end()), held.end());
}

std::vector<Eigen::Vector3d> uncertified_points(const TSpline& spline, const UncertifiedCell& u, double below) {
  auto to_uvw = [&](const Eigen::Vector3d& s) {
    Eigen::Vector3d p = u.uvw_min + s.cwiseProduct(u.uvw_max - u.uvw_min);
    for (int a = 0; a < 3; ++a)
      if (s(a) == 1.0) p(a) = u.uvw_max(a);
    return p;
  };
  std::vector<Eigen::Vector3d> points = {to_uvw(u.bound.lowest_corner_s)};
  const BezierCell cell = extract_bezier_cell(spline, u.cell);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d s(0.5 * i, 0.5 * j, 0.5 * k);
        double value[3];
        Eigen::Matrix3d jacobian;
        evaluate_bezier_cell(cell, s, value, jacobian.data());
        const double det = jacobian.determinant();
        if (det < 0.0 || (below > 0.0 && det < below * jacobian.col(0).norm() * jacobian.col(1).norm() * jacobian.col(2).norm()))
          points.push_back(to_uvw(s));
      }
  return points;
}

Eigen::Vector3d region_min(const TSpline& spline, const SplineUntangleOptions& options) {
  return options.region ? (*options.region)[0] : spline.domain_min();
}

Eigen::Vector3d region_max(const TSpline& spline, const SplineUntangleOptions& options) {
  return options.region ? (*options.region)[1] : spline.domain_max();
}

std::vector<double> region_knot_lines(const TSpline& spline, const SplineUntangleOptions& options, int a) {
  if (!options.region) return spline.knot_lines(a);
  const double lo = (*options.region)[0](a), hi = (*options.region)[1](a);
  std::vector<double> lines{lo};
  for (double t : spline.knot_lines(a))
    if (t > lo && t < hi) lines.push_back(t);
  lines.push_back(hi);
  return lines;
}

bool held_function(const BlendingKnots& knots, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                   const SplineUntangleOptions& options) {
  if (touches_exposed_face(knots, lo, hi, options.exposed_faces)) return true;
  if (!options.region) return false;
  for (int a = 0; a < 3; ++a)
    if (knots[a][0] < lo(a) || knots[a][4] > hi(a)) return true;
  return false;
}

std::array<AxisNodes, 3> make_pass_nodes(const TSpline& spline, const SplineUntangleOptions& options) {
  const Eigen::Vector3d lo = region_min(spline, options), hi = region_max(spline, options);
  const int lattice = options.lattice;
  std::array<AxisNodes, 3> nodes;
  for (int a = 0; a < 3; ++a) {
    std::vector<std::pair<double, char>> t;
    if (options.nodes_per_knot_interval > 0) {
      const double spacing = (hi(a) - lo(a)) * options.energy_stride / lattice;
      const std::vector<double> lines = region_knot_lines(spline, options, a);
      for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
        const double width = lines[i + 1] - lines[i];
        const int per = std::max(options.nodes_per_knot_interval, static_cast<int>(std::ceil(width / spacing - 1e-9)));
        for (int q = 0; q < per; ++q) t.emplace_back(lines[i] + width * (q + 0.5) / per, char(1));
      }
    } else {
      for (int j = 1; j < lattice; j += options.energy_stride)
        t.emplace_back(lo(a) + (hi(a) - lo(a)) * j / lattice, char((j - 1) % options.seed_stride == 0));
    }
    std::sort(t.begin(), t.end());
    const double first = t.front().first - lo(a), last = hi(a) - t.back().first;
    for (double d : options.boundary_layers) {
      t.emplace_back(lo(a) + d * first, char(1));
      t.emplace_back(hi(a) - d * last, char(1));
    }
    std::sort(t.begin(), t.end());
    for (const auto& [value, scanned] : t) {
      nodes[a].t.push_back(value);
      nodes[a].scanned.push_back(scanned);
    }
  }
  return nodes;
}

SplineUntangleResult untangle_pass(TSpline& spline, const std::array<AxisNodes, 3>& nodes, const Eigen::MatrixX3d& uvw,
                                   const Eigen::MatrixX3d& xyz, const std::vector<Eigen::Vector3d>& points,
                                   const SplineUntangleOptions& options, PassSeeds seeds, NodeCache& cache,
                                   const std::vector<Eigen::Vector3d>& held, double tangent_weight) {
  return UntanglePass(spline, nodes, options, cache).run(uvw, xyz, points, seeds, held, tangent_weight);
}

}  // namespace volspline::spline::detail
