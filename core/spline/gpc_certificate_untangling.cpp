// SPDX-License-Identifier: MIT
#include "core/spline/gpc_certificate_untangling.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "core/common/error.h"
#include "core/spline/cell_fold_search.h"
#include "core/spline/edge_crease.h"
#include "core/spline/gpc_jacobian_certificate.h"
#include "core/spline/untangle_energy.h"
#include "core/spline/untangle_pass.h"

namespace volspline::spline {

namespace {

// Barrier nodes per axis per cell in the free functions' supports: the centres of equal parts.
constexpr int kNodesPerCell = 2;
// A polynomial piece spanning up to kPieceCells grid cells along an axis keeps them as barrier
// cells there; one spanning more is cut into kPieceParts equal parts (add_pieces).
constexpr int kPieceCells = 4;
constexpr int kPieceParts = 2;
// Free functions are at most this many times as wide as the narrowest function at the held
// point per axis (2: one dyadic level coarser).
constexpr double kSupportRatio = 2.0;
// Factor on the held points' hinge per round since the uncertified count last fell (in the
// later attempts: the most such rounds in a row so far, the weight not lowered again).
constexpr double kStallWeight = 8.0;
// A round's pass moves only the functions at the cells uncertified in that round where they are
// at most this share of the functions at all the points held so far (certificate_rounds).
constexpr int kLocalPassShare = 5;

// J at a point of a cuboid split into the free functions' part: J = rest + Σ_e x_{column_e}·g_eᵀ.
struct PointJacobian {
  Eigen::Matrix3d full, rest;
  std::vector<int> columns;
  std::vector<Eigen::Vector3d> g;
};

// A guard point of a pass (GpcCertificatePass::add_guard_points) and the number of active cells
// whose 3×3×3 grid has it.
struct GuardPoint {
  int cuboid;
  Eigen::Vector3d p;
  int weight;
};

// PointJacobian's rest, columns and g at a sequence of points, in the order they were asked for.
class PointJacobianStore {
 public:
  std::size_t size() const { return rest_.size(); }
  void clear() {
    rest_.clear();
    start_.assign(1, 0);
    columns_.clear();
    g_.clear();
  }
  // Point q's parts into out's rest, columns and g.
  void get(std::size_t q, PointJacobian& out) const {
    out.rest = rest_[q];
    out.columns.assign(columns_.begin() + start_[q], columns_.begin() + start_[q + 1]);
    out.g.assign(g_.begin() + start_[q], g_.begin() + start_[q + 1]);
  }
  void append(const PointJacobian& j) {
    rest_.push_back(j.rest);
    columns_.insert(columns_.end(), j.columns.begin(), j.columns.end());
    g_.insert(g_.end(), j.g.begin(), j.g.end());
    start_.push_back(static_cast<int>(columns_.size()));
  }

 private:
  std::vector<Eigen::Matrix3d> rest_;
  std::vector<int> start_{0}, columns_;
  std::vector<Eigen::Vector3d> g_;
};

// What a pass computes from the free functions, the other functions' control points and the
// surface samples' factor alone,
// kept from pass to pass: the guard points, the fixed functions' part of J (PointJacobian's
// rest, columns and g) at the barrier nodes and the guard points, and the sample terms. The next round's pass often
// has the same free functions, and only they moved in between; its active cells, and so its
// nodes and guard points, are then the same, in the same order. Valid while the free functions
// are the same and the other control points are as they were when it was filled.
class PassCache {
 public:
  // Empties the cache unless free_ids and surface_factor are the ones it was filled for and every
  // other function's control point is unchanged.
  void prepare(const std::vector<int>& free_ids, const Eigen::MatrixXd& points, double surface_factor) {
    bool valid = free_ids == free_ids_ && points.rows() == points_.rows() && points.cols() == points_.cols() &&
                 surface_factor == surface_factor_;
    if (valid) {
      std::vector<char> is_free(static_cast<std::size_t>(points.rows()), 0);
      for (int f : free_ids) is_free[f] = 1;
      for (Eigen::Index f = 0; f < points.rows() && valid; ++f) valid = is_free[f] || points.row(f) == points_.row(f);
    }
    if (valid) return;
    free_ids_ = free_ids;
    points_ = points;
    surface_factor_ = surface_factor;
    guards_known = false;
    guards.clear();
    nodes.clear();
    guard_parts.clear();
    samples_known = false;
    samples = detail::SampleTerms();
  }

  bool guards_known = false;
  std::vector<GuardPoint> guards;  // add_guard_points' points, if guards_known
  bool samples_known = false;
  detail::SampleTerms samples;  // make_samples' terms, if samples_known
  PointJacobianStore nodes, guard_parts;  // per barrier node, per guard point (a prefix of them)

 private:
  std::vector<int> free_ids_;
  Eigen::MatrixXd points_;
  double surface_factor_ = 1.0;
};

class GpcCertificatePass {
 public:
  // surface_factor: the factor on the data term of the samples on the solid's surface.
  GpcCertificatePass(GpcSpline& spline, const GpcSamples& samples, const SplineUntangleOptions& options,
                     PassCache& cache, double surface_factor)
      : spline_(spline), samples_(samples), options_(options), merges_(spline.num_cuboids()), cache_(cache),
        surface_factor_(surface_factor) {}

  // The number of functions a pass with these seeds would move.
  int free_function_count(const std::vector<std::vector<Eigen::Vector3d>>& seeds) {
    select_free_functions(seeds);
    return static_cast<int>(free_ids_.size());
  }

  // One pass over the held points (per cuboid, in cuboid coordinates), moving the functions at
  // the points `seeds` (held itself, or a part of it); returns the result's free_functions and
  // iterations.
  SplineUntangleResult run(const std::vector<std::vector<Eigen::Vector3d>>& held,
                           const std::vector<std::vector<Eigen::Vector3d>>& seeds, double held_weight) {
    held_weight_ = held_weight;
    SplineUntangleResult result;
    select_free_functions(seeds);
    result.free_functions = static_cast<int>(free_ids_.size());
    if (free_ids_.empty()) return result;
    const Eigen::MatrixXd& points = spline_.points();
    cache_.prepare(free_ids_, points, surface_factor_);
    Eigen::VectorXd x(3 * free_ids_.size());
    for (std::size_t c = 0; c < free_ids_.size(); ++c) x.segment<3>(3 * c) = points.row(free_ids_[c]).transpose();
    points_xyz_.resize(3 * static_cast<std::size_t>(points.rows()));
    for (Eigen::Index f = 0; f < points.rows(); ++f)
      for (int r = 0; r < 3; ++r) points_xyz_[3 * f + r] = points(f, r);
    mark_active_cells();
    Region region;
    double step = 0.0;  // mean knot interval in model units at the nodes
    add_nodes(x, region, step);
    add_held_points(held, x, region);
    add_guard_points(x, region);
    if (!cache_.samples_known) {
      cache_.samples = make_samples();
      cache_.samples_known = true;
    }
    const SampleTerms& samples = cache_.samples;
    detail::RegionEnergyOptions energy_options = detail::region_energy_options(options_, step, 1.0);
    // The folded points are hinge terms, not barrier nodes, so the barrier nodes' being unfolded
    // says nothing about them: the ε continuation runs until the energy settles (a pass stopped
    // at the barrier nodes' margin leaves the held points folded, and the rounds trade the same
    // few cells back and forth).
    energy_options.stop_margin = std::numeric_limits<double>::infinity();
    result.iterations = detail::minimize_region_energy(region, samples, energy_options, x);
    Eigen::MatrixXd moved = points;
    for (std::size_t c = 0; c < free_ids_.size(); ++c) moved.row(free_ids_[c]) = x.segment<3>(3 * c).transpose();
    spline_.set_points(std::move(moved));
    return result;
  }

 private:
  using Region = detail::Region;
  using SampleTerms = detail::SampleTerms;

  // How GpcSpline::basis_at merges a patch cell's functions into global ones: the global ids,
  // increasing, and per id (entries start[i] .. start[i+1]) the positions of its patch functions
  // in the cell's list, in list order.
  struct CellMerge {
    std::vector<int> ids, start, positions;
  };

  const CellMerge& cell_merge(int cuboid, int cell) {
    std::vector<CellMerge>& merges = merges_[cuboid];
    if (merges.empty()) merges.resize(spline_.patch(cuboid).num_cells());
    CellMerge& m = merges[cell];
    if (!m.start.empty()) return m;
    const std::vector<int>& global = spline_.patch_function_ids(cuboid);
    spline_.patch(cuboid).cell_functions(cell, local_ids_);
    m.positions.resize(local_ids_.size());
    std::iota(m.positions.begin(), m.positions.end(), 0);
    std::stable_sort(m.positions.begin(), m.positions.end(),
                     [&](int a, int b) { return global[local_ids_[a]] < global[local_ids_[b]]; });
    for (std::size_t k = 0; k < m.positions.size(); ++k) {
      const int id = global[local_ids_[m.positions[k]]];
      if (m.ids.empty() || m.ids.back() != id) {
        m.ids.push_back(id);
        m.start.push_back(static_cast<int>(k));
      }
    }
    m.start.push_back(static_cast<int>(m.positions.size()));
    return m;
  }

  // GpcSpline::basis_at at one point (the same ids, into ids_, and bits), with each patch cell's
  // merge into global functions worked out once: the value (order (0,0,0)) into values[0], or
  // the three first derivatives into values[0..2].
  enum class Basis { Value, Gradient };
  void global_basis(int cuboid, const Eigen::Vector3d& uvw, Basis kind, std::vector<double>* values) {
    const int cell = spline_.cell_of(cuboid, uvw);  // throws outside the cuboid
    const TSpline& patch = spline_.patch(cuboid);
    const auto& size = spline_.domain().cuboids[cuboid].size;
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p(a) = std::clamp(uvw(a), 0.0, size[a]);
    const CellMerge& m = cell_merge(cuboid, cell);
    ids_ = m.ids;
    int num = 1;
    if (kind == Basis::Value) {
      patch.basis_at(p, {0, 0, 0}, local_ids_, local_values_[0]);
    } else {
      patch.basis_gradient_at(p, local_ids_, local_values_);
      num = 3;
    }
    const Eigen::VectorXd& w = patch.weights();
    for (int o = 0; o < num; ++o) {
      const std::vector<double>& local = local_values_[o];
      std::vector<double>& out = values[o];
      out.resize(m.ids.size());
      for (std::size_t i = 0; i < m.ids.size(); ++i) {
        int k = m.positions[m.start[i]];
        double sum = w(local_ids_[k]) * local[k];
        for (int e = m.start[i] + 1; e < m.start[i + 1]; ++e) {
          k = m.positions[e];
          sum += w(local_ids_[k]) * local[k];
        }
        out[i] = sum;
      }
    }
  }

  // J at (cuboid, uvw) with the free functions' part apart (x: their current points), into a
  // buffer reused from call to call (valid until the next call). The fixed functions' points are
  // read from points_xyz_ (three adjacent values per function).
  // store (or null): the parts of the points asked for so far with it, in order, this one at
  // `index` if the store has it, appended if it has the points before it only.
  const PointJacobian& jacobian_at(int cuboid, const Eigen::Vector3d& uvw, const Eigen::VectorXd& x,
                                   PointJacobianStore* store = nullptr, std::size_t index = 0) {
    PointJacobian& out = point_;
    if (store && index < store->size()) {
      store->get(index, out);
      out.full = out.rest;
      for (std::size_t e = 0; e < out.columns.size(); ++e)
        out.full += x.segment<3>(3 * out.columns[e]) * out.g[e].transpose();
      return out;
    }
    global_basis(cuboid, uvw, Basis::Gradient, gradient_.data());
    out.columns.clear();
    out.g.clear();
    // rest(r, a) += p(r)·g(a) per fixed function, in id order (the bits of rest += p·gᵀ).
    double rest[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (std::size_t q = 0; q < ids_.size(); ++q) {
      const double g[3] = {gradient_[0][q], gradient_[1][q], gradient_[2][q]};
      const int c = column_of_[ids_[q]];
      if (c < 0) {
        const double* p = points_xyz_.data() + 3 * static_cast<std::size_t>(ids_[q]);
        for (int a = 0; a < 3; ++a)
          for (int r = 0; r < 3; ++r) rest[r + 3 * a] += p[r] * g[a];
      } else if (g[0] != 0.0 || g[1] != 0.0 || g[2] != 0.0) {
        out.columns.push_back(c);
        out.g.emplace_back(g[0], g[1], g[2]);
      }
    }
    out.rest = Eigen::Map<const Eigen::Matrix3d>(rest);
    if (store && index == store->size()) store->append(out);
    out.full = out.rest;
    for (std::size_t e = 0; e < out.columns.size(); ++e) out.full += x.segment<3>(3 * out.columns[e]) * out.g[e].transpose();
    return out;
  }

  // The global functions whose value or gradient is non-zero at a held point and whose support
  // is at most kSupportRatio times the narrowest such support there along each axis (in a
  // hierarchical spline the finest functions at the point and those one level coarser: the
  // coarser ones would make the pass global), in id order.
  void select_free_functions(const std::vector<std::vector<Eigen::Vector3d>>& held) {
    column_of_.assign(spline_.num_functions(), -1);
    std::vector<double> values;
    std::vector<int> at_point;
    for (int cuboid = 0; cuboid < spline_.num_cuboids(); ++cuboid) {
      const TSpline& patch = spline_.patch(cuboid);
      const std::vector<int>& global = spline_.patch_function_ids(cuboid);
      auto width = [&](int f, int a) { return patch.knots()[f][a][4] - patch.knots()[f][a][0]; };
      for (const Eigen::Vector3d& p : held[cuboid]) {
        at_point.clear();
        for (int order = 0; order < 4; ++order) {
          std::array<int, 3> derivative = {0, 0, 0};
          if (order < 3) derivative[order] = 1;
          patch.basis_at(p, derivative, ids_, values);
          for (std::size_t q = 0; q < ids_.size(); ++q)
            if (values[q] != 0.0) at_point.push_back(ids_[q]);
        }
        Eigen::Vector3d narrowest = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
        for (int f : at_point)
          for (int a = 0; a < 3; ++a) narrowest(a) = std::min(narrowest(a), width(f, a));
        for (int f : at_point) {
          bool fine = true;
          for (int a = 0; a < 3; ++a) fine = fine && width(f, a) <= kSupportRatio * narrowest(a) * (1.0 + 1e-9);
          if (fine) column_of_[global[f]] = 0;
        }
      }
    }
    free_ids_.clear();
    for (int f = 0; f < spline_.num_functions(); ++f)
      if (column_of_[f] >= 0) {
        column_of_[f] = static_cast<int>(free_ids_.size());
        free_ids_.push_back(f);
      }
  }

  // Per cuboid, the patch cells inside its box where a free function is non-zero, and the
  // polynomial pieces they make up (pieces_).
  void mark_active_cells() {
    active_.assign(spline_.num_cuboids(), {});
    pieces_.clear();
    std::vector<int> local;
    std::vector<std::array<double, 6>> boxes;  // per active cell of the cuboid, in cell order
    std::vector<int> cells;
    for (int cuboid = 0; cuboid < spline_.num_cuboids(); ++cuboid) {
      const TSpline& patch = spline_.patch(cuboid);
      const std::vector<int>& global = spline_.patch_function_ids(cuboid);
      const auto& size = spline_.domain().cuboids[cuboid].size;
      std::vector<char>& active = active_[cuboid];
      active.assign(patch.num_cells(), 0);
      boxes.clear();
      cells.clear();
      for (int cell = 0; cell < patch.num_cells(); ++cell) {
        const std::array<int, 3> k = patch.cell_index(cell);
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
          const double tol = 1e-9 * size[a];
          inside = inside && patch.knot_lines(a)[k[a]] >= -tol && patch.knot_lines(a)[k[a] + 1] <= size[a] + tol;
        }
        if (!inside) continue;
        patch.cell_functions(cell, local);
        active[cell] = std::any_of(local.begin(), local.end(), [&](int f) { return column_of_[global[f]] >= 0; });
        if (!active[cell]) continue;
        cells.push_back(cell);
        boxes.push_back(piece_box(patch, cell, local, size));
      }
      add_pieces(cuboid, cells, boxes);
    }
  }

  // The polynomial piece of the patch holding cell (of functions `local`): per axis the widest
  // interval around the cell that no knot of those functions crosses, cut to the cuboid box. The
  // patch's knot-line grid carries every line of every function of the cuboid, so a split's
  // lines cut cells far from where its functions reach; J is one polynomial over such a piece
  // (Eq. 4.3), and the barrier's nodes and guards belong to it, not to the grid's cells.
  static std::array<double, 6> piece_box(const TSpline& patch, int cell, const std::vector<int>& local,
                                         const std::array<double, 3>& size) {
    const std::array<int, 3> k = patch.cell_index(cell);
    std::array<double, 6> box;
    for (int a = 0; a < 3; ++a) {
      const double c0 = patch.knot_lines(a)[k[a]], c1 = patch.knot_lines(a)[k[a] + 1];
      double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
      for (int f : local)
        for (double t : patch.knots()[f][a]) {
          if (t <= c0) lo = std::max(lo, t);
          if (t >= c1) hi = std::min(hi, t);
        }
      box[a] = std::max(lo, std::min(c0, 0.0));
      box[a + 3] = std::min(hi, std::max(c1, size[a]));
    }
    return box;
  }

  // Appends the cuboid's barrier cells to pieces_, in the order of their first grid cell. The
  // active cells (increasing, with their piece_box) sharing a box are one polynomial piece if they
  // are every grid cell in it (then they have the same functions). Along an axis where a piece
  // spans up to kPieceCells grid cells its barrier cells are those cells, as for a spline split
  // a level or two below it; where it spans more (lines of deeper splits elsewhere in the
  // cuboid), kPieceParts equal parts, so far splits no longer multiply its nodes. A cell whose box
  // is not a whole piece is its own barrier cell.
  void add_pieces(int cuboid, const std::vector<int>& cells, const std::vector<std::array<double, 6>>& boxes) {
    const TSpline& patch = spline_.patch(cuboid);
    std::vector<int> order(cells.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return boxes[a] < boxes[b]; });
    std::vector<int> group(cells.size(), -1);  // per active cell: the first cell of its piece (−1: none)
    // Per piece's first cell: grid cells per axis, and the grid index of its first cell per axis.
    std::vector<std::array<std::size_t, 3>> spans(cells.size());
    std::vector<std::array<int, 3>> firsts(cells.size());
    for (std::size_t i = 0; i < order.size();) {
      std::size_t j = i;
      while (j < order.size() && boxes[order[j]] == boxes[order[i]]) ++j;
      const std::array<double, 6>& box = boxes[order[i]];
      std::array<std::size_t, 3> span;
      std::array<int, 3> lead;
      for (int a = 0; a < 3; ++a) {
        const std::vector<double>& lines = patch.knot_lines(a);
        const auto first = std::lower_bound(lines.begin(), lines.end(), box[a]);
        const auto last = std::upper_bound(lines.begin(), lines.end(), box[a + 3]);
        span[a] = static_cast<std::size_t>(std::max<std::ptrdiff_t>(last - first - 1, 0));
        lead[a] = static_cast<int>(first - lines.begin());
      }
      if (span[0] * span[1] * span[2] == j - i) {
        std::vector<int> members(order.begin() + static_cast<std::ptrdiff_t>(i), order.begin() + static_cast<std::ptrdiff_t>(j));
        const int head = *std::min_element(members.begin(), members.end());
        for (int q : members) group[q] = head;
        spans[head] = span;
        firsts[head] = lead;
      }
      i = j;
    }
    std::vector<std::uint64_t> emitted(cells.size(), 0);  // per piece's first cell: parts emitted
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::array<int, 3> k = patch.cell_index(cells[i]);
      Piece piece{cuboid, {}, {}};
      for (int a = 0; a < 3; ++a) {
        piece.lo(a) = patch.knot_lines(a)[k[a]];
        piece.hi(a) = patch.knot_lines(a)[k[a] + 1];
      }
      const int head = group[i];
      if (head >= 0) {
        const std::array<double, 6>& box = boxes[i];
        int part = 0;  // the barrier cell's position in the piece, base-kPieceCells digits w, v, u
        bool whole_cells = true;
        for (int a = 2; a >= 0; --a) {
          part *= kPieceCells;
          if (spans[head][a] <= static_cast<std::size_t>(kPieceCells)) {
            part += k[a] - firsts[head][a];
            continue;
          }
          whole_cells = false;
          const double width = (box[a + 3] - box[a]) / kPieceParts;
          const double centre = 0.5 * (piece.lo(a) + piece.hi(a));
          const int q = std::clamp(static_cast<int>((centre - box[a]) / width), 0, kPieceParts - 1);
          part += q;
          piece.lo(a) = box[a] + q * width;
          piece.hi(a) = q == kPieceParts - 1 ? box[a + 3] : box[a] + (q + 1) * width;
        }
        if (!whole_cells) {
          const std::uint64_t bit = std::uint64_t{1} << part;
          if (emitted[head] & bit) continue;
          emitted[head] |= bit;
        }
      }
      pieces_.push_back(piece);
    }
  }

  // Barrier nodes: kNodesPerCell³ per barrier cell (pieces_), their rows (with S⁻¹ applied) and fixed parts;
  // step: the mean knot interval in model units there.
  void add_nodes(const Eigen::VectorXd& x, Region& region, double& step) {
    std::vector<Eigen::Matrix3d> full;
    std::vector<int> start{0}, columns;
    std::vector<Eigen::Vector3d> g;
    double step_sum = 0.0;
    for (const Piece& piece : pieces_) {
      const Eigen::Vector3d width = piece.hi - piece.lo;
      for (int n = 0; n < kNodesPerCell * kNodesPerCell * kNodesPerCell; ++n) {
        const Eigen::Vector3d s((n % kNodesPerCell + 0.5) / kNodesPerCell,
                                (n / kNodesPerCell % kNodesPerCell + 0.5) / kNodesPerCell,
                                (n / (kNodesPerCell * kNodesPerCell) + 0.5) / kNodesPerCell);
        const PointJacobian& j = jacobian_at(piece.cuboid, piece.lo + s.cwiseProduct(width), x, &cache_.nodes, full.size());
        full.push_back(j.full);
        columns.insert(columns.end(), j.columns.begin(), j.columns.end());
        g.insert(g.end(), j.g.begin(), j.g.end());
        start.push_back(static_cast<int>(columns.size()));
        const Eigen::Vector3d norms(j.full.col(0).norm(), j.full.col(1).norm(), j.full.col(2).norm());
        region.mean_scale += norms;
        step_sum += norms.dot(width) / 3.0;
      }
    }
    const std::size_t count = full.size();
    region.mean_scale /= std::max<std::size_t>(count, 1);
    step = count ? step_sum / count : 1.0;
    region.rows = detail::NodeJacobians(std::move(start), std::move(columns), g);
    std::vector<double> x_padded;
    detail::NodeJacobians::pad(x, x_padded);
    for (std::size_t q = 0; q < count; ++q) {
      const Eigen::Matrix3d s = detail::inverse_reference_shape(full[q], region.mean_scale);
      region.inverse_reference.push_back(s);
      region.rows.transform(q, s);
      region.fixed.push_back(full[q] * s - region.rows.linear(x_padded.data(), q));
      region.held.push_back(1);  // centres of cell parts: never on a cuboid edge
      region.guarded.push_back(1);  // folded ones too: the ε continuation runs until they unfold
    }
  }

  // The held points, by the hinge (points no free function reaches are left out).
  void add_held_points(const std::vector<std::vector<Eigen::Vector3d>>& held, const Eigen::VectorXd& x,
                       Region& region) {
    for (int cuboid = 0; cuboid < spline_.num_cuboids(); ++cuboid)
      for (const Eigen::Vector3d& p : held[cuboid]) {
        const PointJacobian& j = jacobian_at(cuboid, p, x);
        if (j.columns.empty()) continue;
        region.point_scale.push_back(
            std::max(j.full.col(0).norm() * j.full.col(1).norm() * j.full.col(2).norm(), 1e-300));
        region.point_fixed.push_back(j.rest);
        region.point_target.push_back(options_.min_scaled_jacobian);
        region.point_weight.push_back(held_weight_);
        region.point_columns.insert(region.point_columns.end(), j.columns.begin(), j.columns.end());
        region.point_g.insert(region.point_g.end(), j.g.begin(), j.g.end());
        region.point_start.push_back(static_cast<int>(region.point_columns.size()));
      }
  }

  // Guards: the 3×3×3 grid on every closed barrier cell (pieces_), each held by the hinge at no less than
  // min(min_scaled_jacobian, its scaled Jacobian now), so that unfolding one cell does not fold
  // the cells around it between the barrier's nodes (a cuboid edge, where det J → 0). A grid
  // point shared by k active cells is one hinge of weight k (the same energy, evaluated once).
  void add_guard_points(const Eigen::VectorXd& x, Region& region) {
    if (!cache_.guards_known) {
      cache_.guards = guard_points();
      cache_.guards_known = true;
    }
    for (std::size_t q = 0; q < cache_.guards.size(); ++q) {
      const GuardPoint& guard = cache_.guards[q];
      const PointJacobian& j = jacobian_at(guard.cuboid, guard.p, x, &cache_.guard_parts, q);
      if (j.columns.empty()) continue;
      const double scale = std::max(j.full.col(0).norm() * j.full.col(1).norm() * j.full.col(2).norm(), 1e-300);
      region.point_scale.push_back(scale);
      region.point_fixed.push_back(j.rest);
      region.point_target.push_back(std::min(options_.min_scaled_jacobian, j.full.determinant() / scale));
      region.point_weight.push_back(guard.weight);
      region.point_columns.insert(region.point_columns.end(), j.columns.begin(), j.columns.end());
      region.point_g.insert(region.point_g.end(), j.g.begin(), j.g.end());
      region.point_start.push_back(static_cast<int>(region.point_columns.size()));
    }
  }

  // add_guard_points' points, each once, in the order of their first appearance over the active
  // cells' grids.
  std::vector<GuardPoint> guard_points() const {
    struct Guard {
      int cuboid;
      Eigen::Vector3d p;
      std::size_t first;  // position among all cells' grid points, for the order of the hinges
    };
    std::vector<Guard> guards;
    for (const Piece& piece : pieces_) {
      const auto& size = spline_.domain().cuboids[piece.cuboid].size;
      for (int n = 0; n < 27; ++n) {
        const int idx[3] = {n % 3, n / 3 % 3, n / 9};
        Eigen::Vector3d p;
        for (int a = 0; a < 3; ++a) p(a) = idx[a] == 2 ? piece.hi(a) : idx[a] == 0 ? piece.lo(a) : 0.5 * (piece.lo(a) + piece.hi(a));
        for (int a = 0; a < 3; ++a) p(a) = std::clamp(p(a), 0.0, size[a]);
        guards.push_back({piece.cuboid, p, guards.size()});
      }
    }
    auto same_point = [](const Guard& a, const Guard& b) { return a.cuboid == b.cuboid && a.p == b.p; };
    std::sort(guards.begin(), guards.end(), [](const Guard& a, const Guard& b) {
      if (a.cuboid != b.cuboid) return a.cuboid < b.cuboid;
      if (a.p != b.p) return detail::lexicographic_less(a.p, b.p);
      return a.first < b.first;
    });
    std::vector<std::pair<std::size_t, int>> unique;  // (first position, index into guards), and counts
    std::vector<int> count;
    for (std::size_t g = 0; g < guards.size(); ++g) {
      if (g > 0 && same_point(guards[g - 1], guards[g])) {
        ++count.back();
        continue;
      }
      unique.emplace_back(guards[g].first, static_cast<int>(g));
      count.push_back(1);
    }
    std::vector<int> order(unique.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return unique[a].first < unique[b].first; });
    std::vector<GuardPoint> out;
    out.reserve(order.size());
    for (int u : order) {
      const Guard& guard = guards[unique[u].second];
      out.push_back({guard.cuboid, guard.p, count[u]});
    }
    return out;
  }

  // True if uvw lies on a face of the cuboid that no other cuboid is glued to (the solid's surface).
  bool on_surface(int cuboid, const Eigen::Vector3d& uvw) const {
    const polycube::GpcCuboid& cu = spline_.domain().cuboids[cuboid];
    for (int f = 0; f < 6; ++f) {
      if (cu.face_interface[f] >= 0) continue;
      const double at = f % 2 ? cu.size[f / 2] : 0.0;
      if (std::abs(uvw(f / 2) - at) <= 1e-9 * (1.0 + cu.size[f / 2])) return true;
    }
    return false;
  }

  // The samples in active cells, over the free functions; a surface sample's term scaled by
  // surface_factor_ (its residual by the square root).
  SampleTerms make_samples() {
    SampleTerms terms;
    std::vector<double> values;
    const Eigen::MatrixXd& points = spline_.points();
    for (Eigen::Index s = 0; s < samples_.uvw.rows(); ++s) {
      const int cuboid = samples_.cuboid[s];
      const Eigen::Vector3d uvw = samples_.uvw.row(s).transpose();
      if (!active_[cuboid][spline_.cell_of(cuboid, uvw)]) continue;
      global_basis(cuboid, uvw, Basis::Value, &values);
      Eigen::Vector3d fixed = -samples_.values.row(s).transpose();
      const std::size_t first = terms.column.size();
      for (std::size_t q = 0; q < ids_.size(); ++q) {
        const int c = column_of_[ids_[q]];
        if (c >= 0 && values[q] != 0.0) {
          terms.column.push_back(c);
          terms.b.push_back(values[q]);
        } else {
          fixed += values[q] * points.row(ids_[q]).transpose();
        }
      }
      if (terms.column.size() == first) continue;
      if (surface_factor_ != 1.0 && on_surface(cuboid, uvw)) {
        const double root = std::sqrt(surface_factor_);
        fixed *= root;
        for (std::size_t k = first; k < terms.column.size(); ++k) terms.b[k] *= root;
      }
      terms.offset.push_back(fixed);
      terms.start.push_back(static_cast<int>(terms.column.size()));
    }
    return terms;
  }

  GpcSpline& spline_;
  const GpcSamples& samples_;
  const SplineUntangleOptions& options_;
  std::vector<int> column_of_, free_ids_;  // function → column (−1: fixed); column → function
  std::vector<std::vector<char>> active_;  // per cuboid, per patch cell
  struct Piece {
    int cuboid;
    Eigen::Vector3d lo, hi;  // its box in cuboid coordinates
  };
  std::vector<Piece> pieces_;  // the active cells' polynomial pieces (mark_active_cells)
  std::vector<int> ids_, local_ids_;
  std::array<std::vector<double>, 3> local_values_;
  std::array<std::vector<double>, 3> gradient_;
  std::vector<std::vector<CellMerge>> merges_;  // per cuboid, per patch cell (filled on first use)
  std::vector<double> points_xyz_;  // the control points at the pass's start, x, y, z per function
  PointJacobian point_;             // jacobian_at's result
  PassCache& cache_;
  double held_weight_ = 1.0;        // factor on the held points' hinge
  double surface_factor_ = 1.0;     // factor on the surface samples' data term
};

// After the rounds: the uncertified cells whose det J is negative on or next to a cuboid edge
// between two surface faces get that crease tilted convex, cuboid by cuboid
// (convex_edge_creases on the cuboid's patch, its moved functions written back as global
// control points): det J on such an edge depends on the bd-control-points next to it alone
// (§4.3.1), which the rounds' hinges there only trade between neighbouring cells. Kept if fewer
// cells stay uncertified over all cuboids. uncertified: the spline's uncertified cells.
void tilt_gpc_creases(GpcSpline& spline, const std::vector<UncertifiedCell>& uncertified, SplineUntangleResult& total,
                      JacobianCertificateCache& cache) {
  const int before = static_cast<int>(uncertified.size());
  if (before == 0) return;
  const Eigen::MatrixXd start = spline.points();
  Eigen::MatrixXd points = start;
  int edges = 0;
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    std::vector<UncertifiedCell> cells;
    for (const UncertifiedCell& u : uncertified)
      if (u.cuboid == c) cells.push_back(u);
    if (cells.empty()) continue;
    TSpline patch = spline.patch(c);
    EdgeCreaseOptions crease_options;
    crease_options.exposed_faces = spline.exposed_faces(c);
    const EdgeCreaseResult creases = convex_edge_creases(patch, cells, crease_options, gpc_certificate_options());
    const std::vector<int>& ids = spline.patch_function_ids(c);
    for (int f : creases.moved) points.row(ids[f]) = patch.points().row(f);
    edges += creases.edges;
  }
  int moved = 0;
  for (Eigen::Index f = 0; f < points.rows(); ++f) moved += points.row(f) != start.row(f);
  if (moved == 0) return;
  spline.set_points(points);
  const int after = static_cast<int>(certify_gpc_jacobian(spline, gpc_certificate_options(), &cache).uncertified.size());
  if (after >= before) {
    spline.set_points(start);
    return;
  }
  total.crease_edges = edges;
  total.crease_functions = moved;
  total.final_uncertified = after;
}

// Which functions a round's pass moves.
enum class FreeFunctions {
  AllHeld,       // those at every point held so far, or the CurrentCells ones where they are
                 // at most 1/kLocalPassShare of those
  CurrentCells,  // those at the points of the cells uncertified in this round
};

// The certificate rounds from the spline's points as they are (see untangle_gpc_certificate).
// A pass moving the current cells' functions only (a local pass) starts from the best round's
// points where its round left more uncertified cells than the best one (the points of the cells
// it folded stay held).
SplineUntangleResult certificate_rounds(GpcSpline& spline, const GpcSamples& samples, const SplineUntangleOptions& options,
                                        const Progress& progress, JacobianCertificateCache& certificates,
                                        PassCache& jacobians, FreeFunctions free, double surface_factor,
                                        bool keep_weight_raised) {
  SplineUntangleResult total;
  const int nc = spline.num_cuboids();
  std::vector<std::vector<Eigen::Vector3d>> held(static_cast<std::size_t>(nc));
  detail::CertificateRounds rounds;
  std::vector<UncertifiedCell> best;  // the uncertified cells of the round with the fewest
  int most_stalled = 0;               // the most rounds in a row without a new low so far
  for (int round = 0;; ++round) {
    JacobianCertificate certificate = certify_gpc_jacobian(spline, gpc_certificate_options(), &certificates);
    const int uncertified = static_cast<int>(certificate.uncertified.size());
    if (round == 0) total.initial_uncertified = uncertified;
    if (uncertified < rounds.final_uncertified()) best = certificate.uncertified;
    if (rounds.stop(round, uncertified, spline.points(), options.certificate_rounds)) {
      if (uncertified > rounds.final_uncertified()) spline.set_points(rounds.take_best_points());
      else best = std::move(certificate.uncertified);
      total.final_uncertified = rounds.final_uncertified();
      tilt_gpc_creases(spline, best, total, certificates);
      return total;
    }
    progress.report("untangle certificate " + std::to_string(round + 1) + ": " + std::to_string(uncertified) +
                        " cells uncertified",
                    static_cast<double>(round) / options.certificate_rounds);
    std::vector<std::vector<Eigen::Vector3d>> more(static_cast<std::size_t>(nc));
    for (const UncertifiedCell& u : certificate.uncertified) {
      std::vector<Eigen::Vector3d> points = detail::uncertified_points(spline.patch(u.cuboid), u, options.min_scaled_jacobian);
      // The fold itself: the certificate's lowest box corner and the 3×3×3 grid can both miss
      // it (an Undecided cell's lowest corner is often positive), and a fold no hinge holds is
      // never pulled open.
      const CellJacobianPoint fold =
          lowest_jacobian_point(extract_bezier_cell(spline.patch(u.cuboid), u.cell), u.bound.lowest_corner_s);
      Eigen::Vector3d p = u.uvw_min + fold.s.cwiseProduct(u.uvw_max - u.uvw_min);
      for (int a = 0; a < 3; ++a)
        if (fold.s(a) == 1.0) p(a) = u.uvw_max(a);
      points.push_back(p);
      more[u.cuboid].insert(more[u.cuboid].end(), points.begin(), points.end());
    }
    std::vector<std::vector<Eigen::Vector3d>> current = more;
    for (std::vector<Eigen::Vector3d>& c : current) std::sort(c.begin(), c.end(), detail::lexicographic_less);
    for (int c = 0; c < nc; ++c) detail::merge_points(held[c], std::move(more[c]));
    // A pass costs in proportion to the functions it moves: once the cells left need a small
    // part of the held points' functions, a pass over all of them spends most of its time on
    // cells certified already, and re-folds some of them between its guard points.
    bool local = free == FreeFunctions::CurrentCells;
    if (!local) {
      GpcCertificatePass counter(spline, samples, options, jacobians, surface_factor);
      local = kLocalPassShare * counter.free_function_count(current) <= counter.free_function_count(held);
    }
    if (local && uncertified > rounds.final_uncertified()) spline.set_points(rounds.best_points());
    most_stalled = std::max(most_stalled, rounds.stalled());
    const double held_weight = std::pow(kStallWeight, keep_weight_raised ? most_stalled : rounds.stalled());
    const SplineUntangleResult r = GpcCertificatePass(spline, samples, options, jacobians, surface_factor)
                                       .run(held, local ? current : held, held_weight);
    ++total.certificate_passes;
    total.local_passes += local;
    total.free_functions += r.free_functions;
    total.iterations += r.iterations;
  }
}

}  // namespace

SplineUntangleResult untangle_gpc_certificate(GpcSpline& spline, const GpcSamples& samples,
                                              const SplineUntangleOptions& options, const Progress& progress,
                                              JacobianCertificateCache* cache) {
  if (spline.dimension() != 3)
    throw Error("GPC certificate untangling: the spline has dimension " + std::to_string(spline.dimension()) +
                ", expected 3 (geometry)");
  assert(options.certificate_rounds >= 0 && options.surface_data_factor >= 1.0 && options.certificate_attempts >= 1 &&
         samples.uvw.rows() == samples.values.rows());
  JacobianCertificateCache own_cache;
  JacobianCertificateCache& certificates = cache ? *cache : own_cache;
  const Eigen::MatrixXd start = spline.points();
  // The attempts, each from the start, until one certifies every cell:
  // 1. passes over every point held so far, the surface samples held surface_data_factor times
  //    as hard as the interior ones; local passes once the cells left need few of those
  //    functions (FreeFunctions::AllHeld);
  // 2. the same with every sample alike, where holding the surface keeps a fold shut;
  // 3. local passes only: those moving the functions at the cells uncertified in their round.
  //    A pass over every point held so far moves most of the spline and re-folds cells that
  //    earlier rounds certified between its guard points, so the rounds trade cells back and
  //    forth around a cell that needs many of them; local passes do not, but converge slower
  //    where hundreds of cells fold and move the surface more.
  // The attempt whose certificate is better (fewer uncertified cells, then the higher
  // det_j_lower_bound_rel) is kept. In the first attempt the held points' weight falls back to 1
  // whenever the uncertified count reaches a new low; in the later ones it stays at the highest
  // it reached. Falling back lets the next pass's data term re-fold cells held so far: the
  // count then alternates between few and many uncertified cells until the rounds run out
  // (held-out twocup). Kept raised with the surface held hard, the hinge pulls the surface
  // instead of opening the fold (the held-out chair's first attempt then stays uncertified).
  struct Attempt {
    FreeFunctions free;
    double surface_factor;
    bool keep_weight_raised;
  };
  std::vector<Attempt> attempts = {{FreeFunctions::AllHeld, options.surface_data_factor, false}};
  if (options.surface_data_factor != 1.0) attempts.push_back({FreeFunctions::AllHeld, 1.0, true});
  attempts.push_back({FreeFunctions::CurrentCells, 1.0, true});
  attempts.resize(std::min<std::size_t>(attempts.size(), static_cast<std::size_t>(options.certificate_attempts)));
  PassCache jacobians;
  SplineUntangleResult kept, sum;
  Eigen::MatrixXd kept_points;
  double kept_bound = -std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < attempts.size(); ++a) {
    if (a > 0) spline.set_points(start);
    const SplineUntangleResult r = certificate_rounds(spline, samples, options, progress, certificates, jacobians,
                                                      attempts[a].free, attempts[a].surface_factor,
                                                      attempts[a].keep_weight_raised);
    sum.certificate_passes += r.certificate_passes;
    sum.local_passes += r.local_passes;
    sum.free_functions += r.free_functions;
    sum.iterations += r.iterations;
    double bound = 0.0;
    if (r.final_uncertified > 0)
      bound = certify_gpc_jacobian(spline, gpc_certificate_options(), &certificates).det_j_lower_bound_rel;
    if (a == 0 || r.final_uncertified < kept.final_uncertified ||
        (r.final_uncertified == kept.final_uncertified && bound > kept_bound)) {
      kept = r;
      kept_bound = bound;
      kept_points = spline.points();
    }
    if (kept.final_uncertified == 0 || options.certificate_rounds == 0) break;
  }
  spline.set_points(std::move(kept_points));
  kept.certificate_passes = sum.certificate_passes;
  kept.local_passes = sum.local_passes;
  kept.free_functions = sum.free_functions;
  kept.iterations = sum.iterations;
  return kept;
}

}  // namespace volspline::spline
