// SPDX-License-Identifier: MIT
#include "core/spline/spline_untangling.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>

#if defined(__GNUC__) && defined(__x86_64__) && !defined(__EMSCRIPTEN__)
#include <immintrin.h>
#define VOLSPLINE_AVX2_ROWS 1
#endif

#include "core/mesh/hex_quality.h"
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
// Weight of the scattered nodes' hinge (tuning, rings 1 in all passes): 100 left bunny 9 folded
// points of 64³, 1000 left 4, 10⁴ left 19 (it then outweighs the barrier that holds the nodes).
constexpr double kHingeWeight = 1000.0;

bool lexicographic_less(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
}

// The samples' terms, one array each: F(x) − xyz_s = offset_s + Σ_e x_{column_e} b_e over
// e in start_s .. start_{s+1} − 1 (offset: the fixed functions' part minus the target).
struct SampleTerms {
  std::vector<Eigen::Vector3d> offset;
  std::vector<int> start{0}, column;
  std::vector<double> b;
  int size() const { return static_cast<int>(offset.size()); }
};

// A free function on the lattice: the box of nodes where it may be non-zero, first[a] ..
// first[a] + count[a] − 1 per axis, and the factors of w·∇B there: w·N_a and w·N_a' per axis
// (the weight folded into axis 0), so w·∇B = (n'₀n₁n₂, n₀n'₁n₂, n₀n₁n'₂).
struct FreeFunction {
  std::array<int, 3> first{}, count{};
  std::array<std::vector<double>, 3> value, slope;
};

// The Jacobians at the region nodes as a fixed linear map of the free control points (the
// knots do not change while untangling): per node, the free functions non-zero there and their
// w·∇B (compressed rows), so J(node) = fixed + Σ_c x_c·(w∇B_c)ᵀ sums in registers, and the
// energy's gradient scatters back through the same rows in the same sweep. The row entries are
// stored in single precision (sums in double): the sweeps' memory traffic counts (bunny's first
// pass streams 1.7M entries twice per iteration; doubles were 4 % slower), and the rounding only
// perturbs the search's model of how J changes with x, not J itself (fixed is made with the same
// rows, so J at the start point is exact, and the spline is evaluated anew after the pass).
class NodeJacobians {
 public:
  NodeJacobians() = default;
  // Rows from the functions' node boxes; node_index: lattice node → region node (−1: none),
  // sizes: lattice nodes per axis, num_nodes: region nodes.
  NodeJacobians(const std::vector<FreeFunction>& functions, const std::vector<int>& node_index,
                std::array<int, 3> sizes, std::size_t num_nodes)
      : start_(num_nodes + 1, 0) {
    auto for_each_entry = [&](auto&& visit) {
      for (std::size_t c = 0; c < functions.size(); ++c) {
        const FreeFunction& f = functions[c];
        for (int k = 0; k < f.count[2]; ++k)
          for (int j = 0; j < f.count[1]; ++j)
            for (int i = 0; i < f.count[0]; ++i) {
              const Eigen::Vector3d g(f.slope[0][i] * f.value[1][j] * f.value[2][k],
                                      f.value[0][i] * f.slope[1][j] * f.value[2][k],
                                      f.value[0][i] * f.value[1][j] * f.slope[2][k]);
              if (g.isZero(0.0)) continue;
              const int node = f.first[0] + i + sizes[0] * (f.first[1] + j + sizes[1] * (f.first[2] + k));
              visit(node_index[node], static_cast<int>(c), g);
            }
      }
    };
    for_each_entry([&](int q, int, const Eigen::Vector3d&) { ++start_[q + 1]; });
    for (std::size_t q = 0; q < num_nodes; ++q) start_[q + 1] += start_[q];
    column_.resize(start_.back());
    gradient_.resize(3 * static_cast<std::size_t>(start_.back()));
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for_each_entry([&](int q, int c, const Eigen::Vector3d& g) {  // columns ascending per row
      const int e = fill[q]++;
      column_[e] = c;
      for (int a = 0; a < 3; ++a) gradient_[3 * e + a] = static_cast<float>(g(a));
    });
  }

  // The free control points x (3 per column) padded to 4 per column (the 4th is 0), as the
  // sweeps read them and write gradients: one 4-lane load or store per entry.
  static void pad(const Eigen::VectorXd& x, std::vector<double>& x4) {
    x4.assign(x.size() / 3 * 4, 0.0);
    for (Eigen::Index c = 0; c < x.size() / 3; ++c)
      for (int r = 0; r < 3; ++r) x4[4 * c + r] = x(3 * c + r);
  }
  static void unpad(const std::vector<double>& x4, Eigen::VectorXd& x) {
    for (Eigen::Index c = 0; c < x.size() / 3; ++c)
      for (int r = 0; r < 3; ++r) x(3 * c + r) = x4[4 * c + r];
  }

  // Σ_c x_c·(w∇B_c)ᵀ at node q; x4: padded (see pad).
  Eigen::Matrix3d linear(const double* x4, std::size_t q) const {
#ifdef VOLSPLINE_AVX2_ROWS
    if (avx2_) return linear_avx2(x4, q);
#endif
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    for (int e = start_[q]; e < start_[q + 1]; ++e) {
      const float* g = gradient_.data() + 3 * e;
      const double* xc = x4 + 4 * column_[e];
      for (int a = 0; a < 3; ++a)
        for (int r = 0; r < 3; ++r) m(r, a) += xc[r] * double(g[a]);
    }
    return m;
  }

  // Rows of node q times s (J·s = fixed·s + Σ_c x_c·(sᵀ w∇B_c)ᵀ): the energy then sees J·S⁻¹.
  void transform(std::size_t q, const Eigen::Matrix3d& s) {
    for (int e = start_[q]; e < start_[q + 1]; ++e) {
      float* g = gradient_.data() + 3 * e;
      const Eigen::Vector3d t = s.transpose() * Eigen::Vector3d(g[0], g[1], g[2]);
      for (int a = 0; a < 3; ++a) g[a] = static_cast<float>(t(a));
    }
  }

  // gradient_c += d·g_c(q) for the functions at node q (g: w∇B, or S⁻ᵀw∇B after transform;
  // d = ∂E/∂J, or ∂E/∂(J·S⁻¹)); gradient4: padded (see pad).
  void add_gradient(const Eigen::Matrix3d& d, std::size_t q, double* gradient4) const {
#ifdef VOLSPLINE_AVX2_ROWS
    if (avx2_) return add_gradient_avx2(d, q, gradient4);
#endif
    for (int e = start_[q]; e < start_[q + 1]; ++e) {
      const float* g = gradient_.data() + 3 * e;
      Eigen::Map<Eigen::Vector3d>(gradient4 + 4 * column_[e]) +=
          d.col(0) * double(g[0]) + d.col(1) * double(g[1]) + d.col(2) * double(g[2]);
    }
  }

 private:
#ifdef VOLSPLINE_AVX2_ROWS
  // The row sweeps with one 4-lane register per column of J (lane 3 unused): the same
  // products and sums per entry as the scalar loops, in the same order, and no FMA (the
  // target is avx2 alone), so both paths give the same bits; about twice as fast on bunny.
  // (p0, p1, p2, 0) and back: 128-bit and scalar moves (masked moves are slow on some CPUs).
  __attribute__((target("avx2"), always_inline)) static __m256d load3(const double* p) {
    return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_load_sd(p + 2), 1);
  }
  __attribute__((target("avx2"), always_inline)) static void store3(double* p, __m256d v) {
    _mm_storeu_pd(p, _mm256_castpd256_pd128(v));
    _mm_store_sd(p + 2, _mm256_extractf128_pd(v, 1));
  }
  __attribute__((target("avx2"), always_inline)) static __m256d broadcast(const float* g) {
    return _mm256_cvtps_pd(_mm_broadcast_ss(g));  // exact, as double(*g)
  }
  __attribute__((target("avx2"))) Eigen::Matrix3d linear_avx2(const double* x, std::size_t q) const {
    __m256d m0 = _mm256_setzero_pd(), m1 = _mm256_setzero_pd(), m2 = _mm256_setzero_pd();
    for (int e = start_[q]; e < start_[q + 1]; ++e) {
      const float* g = gradient_.data() + 3 * e;
      const __m256d xc = _mm256_loadu_pd(x + 4 * column_[e]);
      m0 = _mm256_add_pd(m0, _mm256_mul_pd(xc, broadcast(g)));
      m1 = _mm256_add_pd(m1, _mm256_mul_pd(xc, broadcast(g + 1)));
      m2 = _mm256_add_pd(m2, _mm256_mul_pd(xc, broadcast(g + 2)));
    }
    Eigen::Matrix3d m;
    store3(m.data(), m0);
    store3(m.data() + 3, m1);
    store3(m.data() + 6, m2);
    return m;
  }
  __attribute__((target("avx2"))) void add_gradient_avx2(const Eigen::Matrix3d& d, std::size_t q,
                                                         double* gradient) const {
    const __m256d d0 = load3(d.data()), d1 = load3(d.data() + 3), d2 = load3(d.data() + 6);
    for (int e = start_[q]; e < start_[q + 1]; ++e) {
      const float* g = gradient_.data() + 3 * e;
      double* out = gradient + 4 * column_[e];
      const __m256d t01 = _mm256_add_pd(_mm256_mul_pd(d0, broadcast(g)), _mm256_mul_pd(d1, broadcast(g + 1)));
      const __m256d t = _mm256_add_pd(t01, _mm256_mul_pd(d2, broadcast(g + 2)));
      _mm256_storeu_pd(out, _mm256_add_pd(_mm256_loadu_pd(out), t));
    }
  }
  bool avx2_ = __builtin_cpu_supports("avx2");
#endif
  std::vector<int> start_, column_;
  std::vector<float> gradient_;  // w∇B (S⁻ᵀw∇B after transform), 3 per entry
};

// The energy's nodes: J·S⁻¹ = fixed + rows(x) at node q (S⁻¹ = inverse_reference[q], the
// inverse of the node's reference shape, already applied to fixed and to the rows).
struct Region {
  NodeJacobians rows;
  std::vector<Eigen::Matrix3d> fixed;
  std::vector<Eigen::Matrix3d> inverse_reference;
  Eigen::Vector3d mean_scale = Eigen::Vector3d::Zero();  // of the column norms of J
  // Nodes that must end unfolded: the scanned ones and those not folded before. A folded node
  // off the scan that the free functions cannot reach (bimba has some) would otherwise hold
  // the ε continuation until its barrier dominates the energy.
  std::vector<char> guarded;
  // Nodes on a cuboid edge (two coordinates on the domain boundary) are rows' fillers only:
  // det J = 0 there wherever the surface is smooth across the edge (three tangents in a plane).
  std::vector<char> held;
  // Scattered nodes (the dense check's bad points of earlier passes), held by a hinge, not by
  // the barrier (some cannot reach its margin): J = fixed + Σ_c x_c·g_cᵀ, g_c = w_c∇B_c there.
  std::vector<Eigen::Matrix3d> point_fixed;
  std::vector<double> point_scale;  // σ: |J e0||J e1||J e2| before the pass
  // Point e's (column, g) entries: point_columns/point_g[point_start[e] .. point_start[e+1]).
  std::vector<int> point_start{0}, point_columns;
  std::vector<Eigen::Vector3d> point_g;
};

// The lattice of one pass, per axis: the nodes' parameters (ascending) and which are scanned.
struct AxisNodes {
  std::vector<double> t;
  std::vector<char> scanned;
};

// Per axis: nodes_per_knot_interval > 0: per interval of the spline's knot lines, the centres
// of equal parts, as many as nodes_per_knot_interval and at least as many as the interval
// holds steps of energy_stride/l (so coarse intervals keep the lattice's density), all scanned;
// 0: the uniform lattice j/l (every energy_stride-th from j = 1, every seed_stride-th scanned).
// Plus the boundary layers at boundary_layers[q] of the first (last) node's distance from the face.
std::array<AxisNodes, 3> make_nodes(const TSpline& spline, int l, const SplineUntangleOptions& options) {
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  std::array<AxisNodes, 3> nodes;
  for (int a = 0; a < 3; ++a) {
    std::vector<std::pair<double, char>> t;
    if (options.nodes_per_knot_interval > 0) {
      const double spacing = (hi(a) - lo(a)) * options.energy_stride / l;
      const std::vector<double>& lines = spline.knot_lines(a);
      for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
        const double width = lines[i + 1] - lines[i];
        const int per = std::max(options.nodes_per_knot_interval, static_cast<int>(std::ceil(width / spacing - 1e-9)));
        for (int q = 0; q < per; ++q) t.emplace_back(lines[i] + width * (q + 0.5) / per, char(1));
      }
    } else {
      for (int j = 1; j < l; j += options.energy_stride)
        t.emplace_back(lo(a) + (hi(a) - lo(a)) * j / l, char((j - 1) % options.seed_stride == 0));
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

// The node Jacobians of the last pass, kept for the next one: the same nodes (passes differ in
// rings only) and the spline as that pass left it need no second evaluation.
struct NodeCache {
  std::array<AxisNodes, 3> nodes;
  std::vector<Eigen::Matrix3d> jacobians;
  bool current = false;  // jacobians hold J at every node of `nodes` for the spline as it is
};

bool same_nodes(const std::array<AxisNodes, 3>& a, const std::array<AxisNodes, 3>& b) {
  for (int k = 0; k < 3; ++k)
    if (a[k].t != b[k].t || a[k].scanned != b[k].scanned) return false;
  return true;
}

// One scan of the lattice l for seeds and one untangling of the points near them; the moved
// control points are written to spline.
// given_nodes: the pass's nodes instead of make_nodes'; seed_from_scan false: only `extra`
// seeds, and no scan after the pass (the report's scan fields are those before it, in the box).
SplineUntangleReport untangle_pass(TSpline& spline, int l, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                                   const std::vector<Eigen::Vector3d>& extra, const SplineUntangleOptions& options,
                                   NodeCache& cache, const std::array<AxisNodes, 3>* given_nodes = nullptr,
                                   bool seed_from_scan = true) {
  SplineUntangleReport report;
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  const std::array<AxisNodes, 3> nodes = given_nodes ? *given_nodes : make_nodes(spline, l, options);
  const std::array<int, 3> sizes = {static_cast<int>(nodes[0].t.size()), static_cast<int>(nodes[1].t.size()),
                                    static_cast<int>(nodes[2].t.size())};
  auto point = [&](int i, int j, int k) { return Eigen::Vector3d(nodes[0].t[i], nodes[1].t[j], nodes[2].t[k]); };
  auto index = [&](int i, int j, int k) { return i + sizes[0] * (j + sizes[1] * k); };
  auto on_edge = [&](int i, int j, int k) {
    const int idx[3] = {i, j, k};
    int faces = 0;
    for (int a = 0; a < 3; ++a) faces += nodes[a].t[idx[a]] == lo(a) || nodes[a].t[idx[a]] == hi(a);
    return faces >= 2;
  };
  auto is_scanned = [&](int i, int j, int k) {
    return nodes[0].scanned[i] && nodes[1].scanned[j] && nodes[2].scanned[k] && !on_edge(i, j, k);
  };
  // J at every node, one tensor-product pass per knot-line cell (refreshed after the solve).
  // Nodes box_lo .. box_hi − 1 per axis are evaluated and scanned: all of them, or (seeds
  // from `extra` only) the box of the free functions' supports.
  std::array<int, 3> box_lo = {0, 0, 0}, box_hi = sizes;
  const bool cached = seed_from_scan && cache.current && same_nodes(cache.nodes, nodes);
  cache.current = false;
  std::vector<Eigen::Matrix3d>& node_jacobians = cache.jacobians;
  node_jacobians.resize(static_cast<std::size_t>(sizes[0]) * sizes[1] * sizes[2]);
  auto evaluate_nodes = [&] {
    std::array<std::vector<double>, 3> coords;
    for (int a = 0; a < 3; ++a) coords[a].assign(nodes[a].t.begin() + box_lo[a], nodes[a].t.begin() + box_hi[a]);
    spline.evaluate_lattice_with_jacobian(coords, [&](int i, int j, int k, const double*, const double* jacobian) {
      node_jacobians[index(i + box_lo[0], j + box_lo[1], k + box_lo[2])] = Eigen::Map<const Eigen::Matrix3d>(jacobian);
    });
  };
  auto jacobian_at = [&](int i, int j, int k) -> const Eigen::Matrix3d& { return node_jacobians[index(i, j, k)]; };
  if (seed_from_scan) {
    if (!cached) evaluate_nodes();
    cache.nodes = nodes;
    cache.current = true;  // until the pass moves control points
  }

  // The scanned points: counts of non-positive ones, the minimum, and the seeds (if asked).
  auto scan = [&](std::vector<std::array<int, 3>>* seeds) {
    report.scanned = 0;
    report.final_negative = 0;
    report.final_min_scaled = 1.0;
    for (int k = box_lo[2]; k < box_hi[2]; ++k)
      for (int j = box_lo[1]; j < box_hi[1]; ++j)
        for (int i = box_lo[0]; i < box_hi[0]; ++i) {
          if (!is_scanned(i, j, k)) continue;
          const double q = mesh::scaled_jacobian(jacobian_at(i, j, k));
          ++report.scanned;
          if (q <= 0.0) ++report.final_negative;
          if (seeds && q < options.min_scaled_jacobian) seeds->push_back({i, j, k});
          report.final_min_scaled = std::min(report.final_min_scaled, q);
        }
  };
  std::vector<std::array<int, 3>> seeds;
  scan(seed_from_scan ? &seeds : nullptr);
  report.seeds = static_cast<int>(seeds.size());
  report.initial_negative = report.final_negative;
  // A bad point of the dense check seeds at its nearest node.
  for (const Eigen::Vector3d& p : extra) {
    std::array<int, 3> s{};
    for (int a = 0; a < 3; ++a) {
      const std::vector<double>& t = nodes[a].t;
      int i = static_cast<int>(std::lower_bound(t.begin(), t.end(), p(a)) - t.begin());
      if (i == static_cast<int>(t.size()) || (i > 0 && p(a) - t[i - 1] < t[i] - p(a))) --i;
      s[a] = i;
    }
    seeds.push_back(s);
  }
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  if (seeds.empty()) return report;

  // Free functions: interior ones acting near a seed, with supports of at most `limit`
  // lattice steps per axis. A seed whose small interior functions carry less than
  // kMinMovableShare of the gradient there (it lies under boundary functions and coarse ones)
  // cannot be unfolded by them: its limit doubles until they do.
  const int n = spline.num_functions();
  const Eigen::VectorXd& w = spline.weights();
  std::vector<int> column_of(n, -1), free_ids;
  std::vector<int> ids;
  std::vector<double> values;
  auto support_steps = [&](int f) {
    double steps = 0.0;
    for (int a = 0; a < 3; ++a) {
      const LocalKnots& r = spline.knots()[f][a];
      steps = std::max(steps, (r[4] - r[0]) / (hi(a) - lo(a)) * l);
    }
    return steps;
  };
  std::array<std::vector<int>, 3> d_ids;
  std::array<std::vector<double>, 3> d_values;
  std::vector<double> visited_limit(static_cast<std::size_t>(sizes[0]) * sizes[1] * sizes[2], 0.0);
  for (const auto& s : seeds) {
    for (int a = 0; a < 3; ++a) {
      std::array<int, 3> order = {0, 0, 0};
      order[a] = 1;
      spline.basis_at(point(s[0], s[1], s[2]), order, d_ids[a], d_values[a]);
    }
    double limit = options.max_support_steps, total = 0.0, movable = 0.0;
    for (;; limit *= 2) {
      total = movable = 0.0;
      for (std::size_t q = 0; q < d_ids[0].size(); ++q) {
        const int f = d_ids[0][q];
        const double g = w(f) * Eigen::Vector3d(d_values[0][q], d_values[1][q], d_values[2][q]).norm();
        total += g;
        if (support_steps(f) <= limit && !touches_exposed_face(spline.knots()[f], lo, hi, options.exposed_faces)) movable += g;
      }
      if (movable >= kMinMovableShare * total || limit >= l) break;
    }
    for (int dk = -options.rings; dk <= options.rings; ++dk)
      for (int dj = -options.rings; dj <= options.rings; ++dj)
        for (int di = -options.rings; di <= options.rings; ++di) {
          const int i = s[0] + di, j = s[1] + dj, k = s[2] + dk;
          if (i < 0 || j < 0 || k < 0 || i >= sizes[0] || j >= sizes[1] || k >= sizes[2]) continue;
          // A node visited with a limit at least as large added every function this visit would.
          double& visited = visited_limit[index(i, j, k)];
          if (visited >= limit) continue;
          visited = limit;
          spline.basis_at(point(i, j, k), {0, 0, 0}, ids, values);
          for (std::size_t q = 0; q < ids.size(); ++q) {
            const int f = ids[q];
            if (values[q] == 0.0 || column_of[f] >= 0 || touches_exposed_face(spline.knots()[f], lo, hi, options.exposed_faces) ||
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
  if (!seed_from_scan) {
    box_lo = sizes;
    box_hi = {0, 0, 0};
    for (int f : free_ids)
      for (int a = 0; a < 3; ++a) {
        const LocalKnots& r = spline.knots()[f][a];
        const std::vector<double>& t = nodes[a].t;
        box_lo[a] = std::min(box_lo[a], static_cast<int>(std::lower_bound(t.begin(), t.end(), r[0]) - t.begin()));
        box_hi[a] = std::max(box_hi[a], static_cast<int>(std::upper_bound(t.begin(), t.end(), r[4]) - t.begin()));
      }
    for (int a = 0; a < 3; ++a) box_hi[a] = std::max(box_hi[a], box_lo[a]);
    evaluate_nodes();
  }

  // Energy points: every lattice node in the support of a free function (so no point the
  // free functions change goes unseen), with the functions' factors of w·∇B on their boxes.
  Eigen::MatrixXd current = spline.points();
  Eigen::VectorXd x(3 * free_ids.size());
  for (std::size_t c = 0; c < free_ids.size(); ++c) x.segment<3>(3 * c) = current.row(free_ids[c]).transpose();
  const Eigen::VectorXd x0 = x;
  std::vector<double> x0_padded;
  NodeJacobians::pad(x0, x0_padded);
  auto make_region = [&]() {
    std::vector<int> node_index(static_cast<std::size_t>(sizes[0]) * sizes[1] * sizes[2], -1);
    std::vector<FreeFunction> functions(free_ids.size());
    for (std::size_t c = 0; c < free_ids.size(); ++c) {
      const int f = free_ids[c];
      FreeFunction& ff = functions[c];
      for (int a = 0; a < 3; ++a) {
        const LocalKnots& r = spline.knots()[f][a];
        // The nodes in the closed support [r0, r4] (the ends add zeros at most).
        const std::vector<double>& t = nodes[a].t;
        const int first = static_cast<int>(std::lower_bound(t.begin(), t.end(), r[0]) - t.begin());
        const int end = static_cast<int>(std::upper_bound(t.begin(), t.end(), r[4]) - t.begin());
        ff.first[a] = first;
        ff.count[a] = std::max(0, end - first);
        const double scale = a == 0 ? w(f) : 1.0;
        const RightEnd right = r[4] == hi(a) ? RightEnd::Closed : RightEnd::Open;  // nodes on the face
        for (int i = 0; i < ff.count[a]; ++i) {
          const BasisDerivatives d = cubic_basis_derivatives(r, t[first + i], right);
          ff.value[a].push_back(scale * d.value);
          ff.slope[a].push_back(scale * d.d1);
        }
      }
      for (int k = 0; k < ff.count[2]; ++k)
        for (int j = 0; j < ff.count[1]; ++j)
          for (int i = 0; i < ff.count[0]; ++i)
            node_index[index(ff.first[0] + i, ff.first[1] + j, ff.first[2] + k)] = 0;
    }
    Region region;
    std::vector<Eigen::Matrix3d> fixed;
    for (int k = 0; k < sizes[2]; ++k)
      for (int j = 0; j < sizes[1]; ++j)
        for (int i = 0; i < sizes[0]; ++i) {
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
    for (const Eigen::Matrix3d& jac : fixed) {
      // Reference: the point's own Jacobian where it is good (the energy is then least where
      // the map already is), else an orthogonal frame of its column lengths, each at least the
      // region's mean: a folded column is short (bunny's faces: the normal derivative), and
      // its own length would make a flat element the target.
      const Eigen::Vector3d norms(jac.col(0).norm(), jac.col(1).norm(), jac.col(2).norm());
      region.inverse_reference.push_back(
          mesh::scaled_jacobian(jac) >= kGoodScaledJacobian
              ? Eigen::Matrix3d(jac.inverse())
              : Eigen::Matrix3d(norms.cwiseMax(region.mean_scale).cwiseMax(1e-300).cwiseInverse().asDiagonal()));
    }
    for (const Eigen::Vector3d& p : extra) {
      Eigen::Matrix3d jac;
      double value[3];
      spline.evaluate_with_jacobian(p, TSplineForm::SemiStandard, value, jac.data());
      std::vector<std::pair<int, Eigen::Vector3d>> entries;
      for (int a = 0; a < 3; ++a) {
        std::array<int, 3> order = {0, 0, 0};
        order[a] = 1;
        spline.basis_at(p, order, d_ids[a], d_values[a]);
      }
      for (std::size_t q = 0; q < d_ids[0].size(); ++q) {
        const int c = column_of[d_ids[0][q]];
        if (c < 0) continue;
        const Eigen::Vector3d g = w(d_ids[0][q]) * Eigen::Vector3d(d_values[0][q], d_values[1][q], d_values[2][q]);
        jac -= x0.segment<3>(3 * c) * g.transpose();
        entries.emplace_back(c, g);
      }
      if (entries.empty()) continue;
      const Eigen::Matrix3d full = jac + [&] {
        Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
        for (const auto& [c, g] : entries) m += x0.segment<3>(3 * c) * g.transpose();
        return m;
      }();
      region.point_scale.push_back(
          std::max(full.col(0).norm() * full.col(1).norm() * full.col(2).norm(), 1e-300));
      region.point_fixed.push_back(jac);
      for (const auto& [c, g] : entries) {
        region.point_columns.push_back(c);
        region.point_g.push_back(g);
      }
      region.point_start.push_back(static_cast<int>(region.point_columns.size()));
    }
    region.rows = NodeJacobians(functions, node_index, sizes, fixed.size());
    // The rows and fixed parts carry S⁻¹, so the energy's sweeps need no 3×3 products: fixed is
    // the part of J·S⁻¹ the free functions do not change.
    for (std::size_t q = 0; q < fixed.size(); ++q) {
      region.rows.transform(q, region.inverse_reference[q]);
      fixed[q] = fixed[q] * region.inverse_reference[q] - region.rows.linear(x0_padded.data(), q);
    }
    region.fixed = std::move(fixed);
    return region;
  };
  const Region region = make_region();
  // One lattice step in model units: the length unit of the data term.
  const double step = (region.mean_scale.array() * (hi - lo).array()).mean() / l;

  SampleTerms samples;
  // Samples in a cell without free functions have no term: known per cell, without the basis.
  std::vector<signed char> cell_has_free(static_cast<std::size_t>(spline.num_cells()), -1);
  for (Eigen::Index s = 0; s < uvw.rows(); ++s) {
    const int cell = spline.cell_of(uvw.row(s).transpose());
    signed char& has_free = cell_has_free[static_cast<std::size_t>(cell)];
    if (has_free < 0) {
      spline.cell_functions(cell, ids);
      has_free = std::any_of(ids.begin(), ids.end(), [&](int f) { return column_of[f] >= 0; });
    }
    if (!has_free) continue;
    spline.basis_at(uvw.row(s).transpose(), {0, 0, 0}, ids, values);
    Eigen::Vector3d fixed = Eigen::Vector3d::Zero();
    const std::size_t first = samples.column.size();
    for (std::size_t q = 0; q < ids.size(); ++q) {
      const double b = w(ids[q]) * values[q];
      if (column_of[ids[q]] >= 0 && b != 0.0) {
        samples.column.push_back(column_of[ids[q]]);
        samples.b.push_back(b);
      } else {
        fixed += b * current.row(ids[q]).transpose();
      }
    }
    if (samples.column.size() == first) continue;
    samples.offset.push_back(fixed - xyz.row(s).transpose());
    samples.start.push_back(static_cast<int>(samples.column.size()));
  }
  report.samples = samples.size();

  const double data_scale = options.data_weight / (step * step);
  const double theta = options.volume_weight;
  const double hinge_target = options.min_scaled_jacobian;
  // Minimizes the energy over the region's nodes: the barrier of Garanzha et al. 2021 (§3, with
  // its ε continuation; the thesis has no untangling step).
  auto solve = [&](const Region& r) {
    const std::size_t num_points = r.fixed.size();
    // The energy's nodes are the held ones (guarded ⊆ held), kFoldoverBatch to a batch; M = J·S⁻¹
    // of a batch is stored as the batch kernel reads it (element k of lane l at 9·kBatch·b + k·kBatch
    // + l), the last batch padded with its last node.
    constexpr int kBatch = param::kFoldoverBatch;
    std::vector<int> held_nodes;
    for (std::size_t q = 0; q < num_points; ++q)
      if (r.held[q]) held_nodes.push_back(static_cast<int>(q));
    const std::size_t num_batches = (held_nodes.size() + kBatch - 1) / kBatch;
    const std::size_t lanes = num_batches * kBatch;
    auto put = [&](std::vector<double>& m, std::size_t h, const Eigen::Matrix3d& value) {
      double* out = m.data() + (h / kBatch) * 9 * kBatch + h % kBatch;
      for (int k = 0; k < 9; ++k) out[k * kBatch] = value.data()[k];
    };
    auto get = [&](const std::vector<double>& m, std::size_t h) {
      const double* in = m.data() + (h / kBatch) * 9 * kBatch + h % kBatch;
      Eigen::Matrix3d value;
      for (int k = 0; k < 9; ++k) value.data()[k] = in[k * kBatch];
      return value;
    };
    // M at every held node from the rows: fixed + rows(y), or rows(y) alone.
    std::vector<double> padded, gradient_padded;
    auto fill = [&](std::vector<double>& m, const Eigen::VectorXd& y, bool with_fixed) {
      m.resize(9 * lanes);
      NodeJacobians::pad(y, padded);
      for (std::size_t h = 0; h < lanes; ++h) {
        const int q = held_nodes[std::min(h, held_nodes.size() - 1)];
        const Eigen::Matrix3d sum = r.rows.linear(padded.data(), q);
        put(m, h, with_fixed ? Eigen::Matrix3d(r.fixed[q] + sum) : sum);
      }
    };
    // jac holds M at jac_x. M is linear in x: along the line search's line x + t·d it is
    // M(x) + t·M_d, so a trial needs no sums over the functions.
    std::vector<double> jac, line_start, line_step;
    Eigen::VectorXd jac_x, line_x, line_d;
    const std::size_t num_extra = r.point_fixed.size();
    std::vector<Eigen::Matrix3d> extra_jac(num_extra), extra_start(num_extra), extra_step(num_extra);
    auto extra_linear = [&](const Eigen::VectorXd& y, std::size_t e) {
      Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
      for (int k = r.point_start[e]; k < r.point_start[e + 1]; ++k)
        m += y.segment<3>(3 * r.point_columns[k]) * r.point_g[k].transpose();
      return m;
    };
    auto jacobians = [&](const Eigen::VectorXd& y) -> const std::vector<double>& {
      if (jac_x.size() != y.size() || jac_x != y) {
        fill(jac, y, true);
        for (std::size_t e = 0; e < num_extra; ++e) extra_jac[e] = r.point_fixed[e] + extra_linear(y, e);
        jac_x = y;
      }
      return jac;
    };
    auto energy = [&](const std::vector<double>& j, const Eigen::VectorXd& y, double eps, Eigen::VectorXd* gradient) {
      double total = 0.0;
      if (gradient) {
        gradient->resize(y.size());  // set whole from gradient_padded below
        gradient_padded.assign(y.size() / 3 * 4, 0.0);
      }
      // The energies are summed and the gradients scattered in node order, as one at a time.
      double out[9 * kBatch], e[kBatch];
      for (std::size_t batch = 0; batch < num_batches; ++batch) {
        const std::size_t first = batch * kBatch;
        const int count = static_cast<int>(std::min<std::size_t>(kBatch, held_nodes.size() - first));
        param::foldover_free_energy_batch(j.data() + batch * 9 * kBatch, eps, theta, e, gradient ? out : nullptr);
        for (int l = 0; l < count; ++l) {
          total += e[l];
          if (!gradient) continue;
          Eigen::Matrix3d df;
          for (int k = 0; k < 9; ++k) df.data()[k] = out[k * kBatch + l];
          r.rows.add_gradient(df, held_nodes[first + l], gradient_padded.data());
        }
      }
      if (gradient) NodeJacobians::unpad(gradient_padded, *gradient);
      // Scattered nodes: the hinge W·max(0, τ − det J/σ)², zero where they are good enough.
      for (std::size_t e = 0; e < num_extra; ++e) {
        const Eigen::Matrix3d& m = extra_jac[e];
        const double gap = hinge_target - m.determinant() / r.point_scale[e];
        if (gap <= 0.0) continue;
        total += kHingeWeight * gap * gap;
        if (!gradient) continue;
        Eigen::Matrix3d cof;  // ∂det/∂J
        cof.col(0) = m.col(1).cross(m.col(2));
        cof.col(1) = m.col(2).cross(m.col(0));
        cof.col(2) = m.col(0).cross(m.col(1));
        const Eigen::Matrix3d d = (-2.0 * kHingeWeight * gap / r.point_scale[e]) * cof;
        for (int k = r.point_start[e]; k < r.point_start[e + 1]; ++k)
          gradient->segment<3>(3 * r.point_columns[k]) += d * r.point_g[k];
      }
      for (int t = 0; t < samples.size(); ++t) {
        Eigen::Vector3d res = samples.offset[t];
        for (int k = samples.start[t]; k < samples.start[t + 1]; ++k)
          res += samples.b[k] * y.segment<3>(3 * samples.column[k]);
        total += data_scale * res.squaredNorm();
        if (!gradient) continue;
        for (int k = samples.start[t]; k < samples.start[t + 1]; ++k)
          gradient->segment<3>(3 * samples.column[k]) += 2.0 * data_scale * samples.b[k] * res;
      }
      return total;
    };
    param::UntangleProblem problem;
    problem.energy = [&](const Eigen::VectorXd& y, double eps, Eigen::VectorXd* gradient) {
      return energy(jacobians(y), y, eps, gradient);
    };
    problem.min_det = [&](const Eigen::VectorXd& y) {
      const std::vector<double>& j = jacobians(y);
      double worst = std::numeric_limits<double>::infinity();
      for (std::size_t h = 0; h < held_nodes.size(); ++h)
        if (r.guarded[held_nodes[h]]) worst = std::min(worst, get(j, h).determinant());
      return worst;
    };
    problem.set_line = [&](const Eigen::VectorXd& y, const Eigen::VectorXd& d) {
      line_start = jacobians(y);
      line_x = y;
      line_d = d;
      fill(line_step, d, false);
      for (std::size_t e = 0; e < num_extra; ++e) {
        extra_start[e] = extra_jac[e];
        extra_step[e] = extra_linear(d, e);
      }
    };
    problem.line_energy = [&](double t, double eps, Eigen::VectorXd* gradient) {
      jac_x = line_x + t * line_d;  // the same bits as the minimizer's x + t·d
      for (std::size_t i = 0; i < jac.size(); ++i) jac[i] = line_start[i] + t * line_step[i];
      for (std::size_t e = 0; e < num_extra; ++e) extra_jac[e] = extra_start[e] + t * extra_step[e];
      return energy(jac, jac_x, eps, gradient);
    };
    param::UntangleOptions untangle_options;
    untangle_options.max_steps = options.max_steps;
    untangle_options.max_inner = options.max_inner;
    untangle_options.stop_min_det = options.stop_margin;
    untangle_options.keep_curvature = true;
    untangle_options.min_sigma = kMinSigma;
    return param::untangle(problem, x, untangle_options);
  };
  report.points = static_cast<int>(region.fixed.size());
  report.iterations = solve(region);

  for (std::size_t c = 0; c < free_ids.size(); ++c) current.row(free_ids[c]) = x.segment<3>(3 * c).transpose();
  spline.set_points(std::move(current));
  cache.current = false;
  if (!seed_from_scan) return report;  // the polish scans its whole lattice itself
  evaluate_nodes();
  cache.current = true;
  scan(nullptr);
  return report;
}

// The dense check between passes: per axis, check_per_interval centres of equal parts of every
// knot interval plus the boundary layers (as make_nodes); its points with scaled Jacobian below
// min_scaled_jacobian that the interior functions can move, in lexicographic order.
std::vector<Eigen::Vector3d> folded_points(const TSpline& spline, const SplineUntangleOptions& options) {
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  std::array<std::vector<double>, 3> coords;
  for (int a = 0; a < 3; ++a) {
    std::vector<double>& t = coords[a];
    const std::vector<double>& lines = spline.knot_lines(a);
    const int per = options.check_per_interval;
    for (std::size_t i = 0; i + 1 < lines.size(); ++i)
      for (int q = 0; q < per; ++q) t.push_back(lines[i] + (lines[i + 1] - lines[i]) * (q + 0.5) / per);
    const double first = t.front() - lo(a), last = hi(a) - t.back();
    for (double d : options.boundary_layers)
      if (d > 0.0) {
        t.push_back(lo(a) + d * first);
        t.push_back(hi(a) - d * last);
      }
    std::sort(t.begin(), t.end());
  }
  std::vector<Eigen::Vector3d> folded;
  spline.evaluate_lattice_with_jacobian(coords, [&](int i, int j, int k, const double*, const double* jacobian) {
    if (mesh::scaled_jacobian(Eigen::Map<const Eigen::Matrix3d>(jacobian)) < options.min_scaled_jacobian)
      folded.emplace_back(coords[0][i], coords[1][j], coords[2][k]);
  });
  // Points where the interior functions carry under kMinMovableShare of |w∇B| (next to the
  // cuboid's edges, or the fitted surface itself flipped) are beyond their reach: left out.
  std::array<std::vector<int>, 3> ids;
  std::array<std::vector<double>, 3> values;
  folded.erase(std::remove_if(folded.begin(), folded.end(),
                              [&](const Eigen::Vector3d& p) {
                                for (int a = 0; a < 3; ++a) {
                                  std::array<int, 3> order = {0, 0, 0};
                                  order[a] = 1;
                                  spline.basis_at(p, order, ids[a], values[a]);
                                }
                                double total = 0.0, movable = 0.0;
                                for (std::size_t q = 0; q < ids[0].size(); ++q) {
                                  const int f = ids[0][q];
                                  const double g = spline.weights()(f) *
                                                   Eigen::Vector3d(values[0][q], values[1][q], values[2][q]).norm();
                                  total += g;
                                  if (!touches_exposed_face(spline.knots()[f], lo, hi, options.exposed_faces)) movable += g;
                                }
                                return movable < kMinMovableShare * total;
                              }),
               folded.end());
  return folded;  // lattice order is lexicographic in (w, v, u); sorted by the caller's merge
}

// The polish lattice: per axis the centres of equal parts of the domain as wide as the finest
// knot interval of any axis (bunny: 1/64, the 64³ cell centres), at least min_per_axis and at
// most max_per_axis of them, all scanned. No boundary layers: 1/512 from the faces det J is at
// its most fragile, and holding them cost bunny 12 s for 175 such points.
std::array<AxisNodes, 3> finest_nodes(const TSpline& spline, int min_per_axis, int max_per_axis) {
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  double finest = 1.0;  // a fraction of the domain's extent
  for (int a = 0; a < 3; ++a) {
    const std::vector<double>& lines = spline.knot_lines(a);
    for (std::size_t i = 0; i + 1 < lines.size(); ++i)
      finest = std::min(finest, (lines[i + 1] - lines[i]) / (hi(a) - lo(a)));
  }
  const int per_axis =
      std::min(max_per_axis, std::max(min_per_axis, static_cast<int>(std::ceil(1.0 / finest - 1e-9))));
  std::array<AxisNodes, 3> nodes;
  for (int a = 0; a < 3; ++a) {
    for (int q = 0; q < per_axis; ++q) nodes[a].t.push_back(lo(a) + (hi(a) - lo(a)) * (q + 0.5) / per_axis);
    nodes[a].scanned.assign(per_axis, 1);
  }
  return nodes;
}

// The lattice points with scaled Jacobian ≤ threshold, in lattice order.
std::vector<Eigen::Vector3d> bad_lattice_points(const TSpline& spline, const std::array<AxisNodes, 3>& nodes,
                                                double threshold) {
  std::vector<Eigen::Vector3d> bad;
  spline.evaluate_lattice_with_jacobian({nodes[0].t, nodes[1].t, nodes[2].t},
                                        [&](int i, int j, int k, const double*, const double* jacobian) {
                                          if (mesh::scaled_jacobian(Eigen::Map<const Eigen::Matrix3d>(jacobian)) <= threshold)
                                            bad.emplace_back(nodes[0].t[i], nodes[1].t[j], nodes[2].t[k]);
                                        });
  std::sort(bad.begin(), bad.end(), lexicographic_less);
  return bad;
}

}  // namespace

SplineUntangleReport untangle_spline(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                                     const SplineUntangleOptions& options, const Progress& progress) {
  assert(spline.dimension() == 3 && uvw.rows() == xyz.rows());
  assert(options.lattice >= 4 && options.seed_stride >= 1 && options.rings >= 0 && options.max_support_steps >= 4);
  assert(options.passes >= 1);
  assert(options.energy_stride >= 1 && options.seed_stride % options.energy_stride == 0);
  assert(options.nodes_per_knot_interval >= 0 && options.stop_margin >= 0.0 && options.stop_margin < 1.0);
  assert(options.check_per_interval >= 0);
  assert(options.polish_rounds >= 0 && options.polish_max_per_axis >= 2);
  assert(std::all_of(options.boundary_layers.begin(), options.boundary_layers.end(),
                     [](double d) { return d >= 0.0 && d < 1.0; }));
  SplineUntangleReport total;
  NodeCache cache;  // node Jacobians from one pass to the next
  SplineUntangleOptions pass_options = options;
  std::vector<Eigen::Vector3d> extra;
  const double steps = options.passes + options.polish_rounds;
  for (int pass = 0; pass < options.passes; ++pass) {
    progress.report("untangle pass " + std::to_string(pass + 1), pass / steps);
    const SplineUntangleReport r = untangle_pass(spline, options.lattice, uvw, xyz, extra, pass_options, cache);
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
    if (options.check_per_interval == 0) {
      if (r.seeds == 0 || r.final_negative == 0) break;
      // Each pass lets coarser functions move: the few seeds the fine ones could not fix.
      pass_options.max_support_steps *= 2;
      continue;
    }
    if (pass + 1 == options.passes) break;  // no pass left to use a check
    // Bad points between the nodes join every later pass as scattered nodes.
    std::vector<Eigen::Vector3d> bad = folded_points(spline, options);
    if (bad.empty() && r.final_negative == 0) break;
    std::sort(bad.begin(), bad.end(), lexicographic_less);
    const std::size_t before = extra.size();
    extra.insert(extra.end(), bad.begin(), bad.end());
    std::inplace_merge(extra.begin(), extra.begin() + before, extra.end(), lexicographic_less);
    // The later passes are seeded by held points: no rings around the seeds and no coarser
    // functions (bunny's 64³ folds 7 → 4 without rings; 15 → 9 and 4.6 → 3.0 s untangling
    // without doubling max_support_steps).
    pass_options.rings = 0;
    extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
    total.check_points = static_cast<int>(extra.size());
  }
  // Polish (not in the thesis): the points of the finest lattice still folded seed local passes
  // whose nodes are that lattice, so the barrier holds every lattice point the free functions
  // touch; the passes above hold their nodes only, and folds between them remain (bunny: 8 of
  // the 64³ cell centres after 3 passes with dense checks).
  if (options.polish_rounds > 0) {
    const std::array<AxisNodes, 3> fine = finest_nodes(spline, options.lattice, options.polish_max_per_axis);
    SplineUntangleOptions polish_options = options;
    polish_options.rings = 0;
    std::size_t previous = std::numeric_limits<std::size_t>::max();
    for (int round = 0; round < options.polish_rounds; ++round) {
      progress.report("untangle polish " + std::to_string(round + 1), (options.passes + round) / steps);
      const std::vector<Eigen::Vector3d> bad = bad_lattice_points(spline, fine, 0.0);
      total.polish_folded = static_cast<int>(bad.size());
      if (bad.empty() || bad.size() >= previous) break;  // done, or no progress
      previous = bad.size();
      const SplineUntangleReport r =
          untangle_pass(spline, options.lattice, uvw, xyz, bad, polish_options, cache, &fine, false);
      ++total.polish_passes;
      total.free_functions += r.free_functions;
      total.iterations += r.iterations;
      if (r.free_functions == 0) break;
      if (round + 1 == options.polish_rounds)
        total.polish_folded = static_cast<int>(bad_lattice_points(spline, fine, 0.0).size());
    }
  }
  return total;
}

}  // namespace volspline::spline
