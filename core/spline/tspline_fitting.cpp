// SPDX-License-Identifier: MIT
#include "core/spline/tspline_fitting.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>

#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/spline/grouped_gram.h"


namespace volspline::spline {

namespace {

// Appends the row Σ_i coefficient·w_i·B_i(uvw) (scaled) to triplets; columns via column_of
// (−1 = not an unknown: the known part goes to `known` times the fixed control point).
struct RowBuilder {
  const TSpline& spline;
  const std::vector<int>& column_of;
  std::vector<int> ids;
  std::vector<double> values;

  // Returns true if some unknown column got an entry.
  bool add(const Eigen::Vector3d& uvw, double scale, int row, std::vector<linalg::Triplet>& out,
           Eigen::RowVector3d& known) {
    spline.basis_at(uvw, {0, 0, 0}, ids, values);
    bool any = false;
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const double v = scale * spline.weights()(ids[k]) * values[k];
      if (v == 0.0) continue;
      const int col = column_of[ids[k]];
      if (col >= 0) {
        out.push_back({row, col, v});
        any = true;
      } else {
        known += v * spline.points().row(ids[k]);
      }
    }
    return any;
  }
};

int automatic_nodes(const TSpline& spline, int axis, int requested) {
  if (requested > 0) return std::max(requested, 3);
  const int intervals = static_cast<int>(spline.knot_lines(axis).size()) - 1;
  return std::clamp(2 * intervals + 1, 9, 65);
}

// Eq. 4.7 rows F(u_g) − (1/6) Σ_nbr F(u_j) at the interior nodes of a uniform grid.
void add_laplacian_rows(RowBuilder& builder, int nodes_requested, double scale,
                        std::vector<linalg::Triplet>& triplets, std::vector<Eigen::RowVector3d>& known,
                        int& rows) {
  const TSpline& spline = builder.spline;
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  std::array<int, 3> n;
  for (int a = 0; a < 3; ++a) n[a] = automatic_nodes(spline, a, nodes_requested);
  auto point = [&](int i, int j, int k) {
    return Eigen::Vector3d(lo.x() + (hi.x() - lo.x()) * i / (n[0] - 1),
                           lo.y() + (hi.y() - lo.y()) * j / (n[1] - 1),
                           lo.z() + (hi.z() - lo.z()) * k / (n[2] - 1));
  };
  for (int k = 1; k + 1 < n[2]; ++k)
    for (int j = 1; j + 1 < n[1]; ++j)
      for (int i = 1; i + 1 < n[0]; ++i) {
        Eigen::RowVector3d rhs = Eigen::RowVector3d::Zero();
        bool any = builder.add(point(i, j, k), scale, rows, triplets, rhs);
        const std::array<std::array<int, 3>, 6> nbrs = {{{i - 1, j, k}, {i + 1, j, k},
                                                         {i, j - 1, k}, {i, j + 1, k},
                                                         {i, j, k - 1}, {i, j, k + 1}}};
        for (const auto& nb : nbrs)
          any = builder.add(point(nb[0], nb[1], nb[2]), -scale / 6.0, rows, triplets, rhs) || any;
        if (!any) continue;  // only fixed control points: a constant row
        known.push_back(rhs);
        ++rows;
      }
}

// The Eq. 4.7 rows scale·(F(u_g) − (1/6) Σ_nbr F(u_j)) at the interior nodes g of a uniform
// grid, over the unknown columns (the fixed functions' part moves to the right side), grouped
// by 2×2×2 blocks of neighbouring nodes: such rows share most of their columns, so each block is
// one dense Gram update (GroupedGram) instead of one sparse outer product per row.
struct FairingRows {
  std::vector<int> group_offsets{0}, group_cols;  // union of the block's row columns, sorted
  std::vector<int> block_offsets{0};              // rows of each block
  std::vector<int> row_offsets{0}, row_cols;      // row entries (sorted columns)
  std::vector<double> row_values;
  std::vector<Eigen::RowVector3d> rhs;
};
FairingRows laplacian_rows(const TSpline& spline, const std::vector<int>& column_of, int n, int nodes_requested,
                           double scale) {
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  std::array<int, 3> nodes;
  for (int a = 0; a < 3; ++a) nodes[a] = automatic_nodes(spline, a, nodes_requested);
  auto node_id = [&](int i, int j, int k) { return i + nodes[0] * (j + nodes[1] * k); };
  // Basis at every grid node, evaluated once: unknown columns with w_i B_i, and the fixed part of F.
  const int num_nodes = nodes[0] * nodes[1] * nodes[2];
  std::vector<int> node_offsets(num_nodes + 1, 0), node_cols;
  std::vector<double> node_values;
  std::vector<Eigen::RowVector3d> node_known(num_nodes);
  std::vector<int> ids;
  std::vector<double> values;
  for (int k = 0; k < nodes[2]; ++k)
    for (int j = 0; j < nodes[1]; ++j)
      for (int i = 0; i < nodes[0]; ++i) {
        const Eigen::Vector3d uvw(lo.x() + (hi.x() - lo.x()) * i / (nodes[0] - 1),
                                  lo.y() + (hi.y() - lo.y()) * j / (nodes[1] - 1),
                                  lo.z() + (hi.z() - lo.z()) * k / (nodes[2] - 1));
        const int id = node_id(i, j, k);
        spline.basis_at(uvw, {0, 0, 0}, ids, values);
        Eigen::RowVector3d known = Eigen::RowVector3d::Zero();
        for (std::size_t q = 0; q < ids.size(); ++q) {
          const double v = spline.weights()(ids[q]) * values[q];
          if (v == 0.0) continue;
          if (column_of[ids[q]] >= 0) {
            node_cols.push_back(column_of[ids[q]]);
            node_values.push_back(v);
          } else {
            known += v * spline.points().row(ids[q]);
          }
        }
        node_known[id] = known;
        node_offsets[id + 1] = static_cast<int>(node_cols.size());
      }
  FairingRows out;
  std::vector<double> accumulator(n, 0.0);
  std::vector<int> marker(n, -1), in_group(n, -1), cols, union_cols;
  int row = 0, group = 0;
  for (int k0 = 1; k0 + 1 < nodes[2]; k0 += 2)
    for (int j0 = 1; j0 + 1 < nodes[1]; j0 += 2)
      for (int i0 = 1; i0 + 1 < nodes[0]; i0 += 2) {
        union_cols.clear();
        for (int k = k0; k < std::min(k0 + 2, nodes[2] - 1); ++k)
          for (int j = j0; j < std::min(j0 + 2, nodes[1] - 1); ++j)
            for (int i = i0; i < std::min(i0 + 2, nodes[0] - 1); ++i) {
              const std::array<int, 7> stencil = {node_id(i, j, k),     node_id(i - 1, j, k), node_id(i + 1, j, k),
                                                  node_id(i, j - 1, k), node_id(i, j + 1, k), node_id(i, j, k - 1),
                                                  node_id(i, j, k + 1)};
              cols.clear();
              Eigen::RowVector3d known = Eigen::RowVector3d::Zero();
              for (int p = 0; p < 7; ++p) {
                const double c = p == 0 ? scale : -scale / 6.0;
                known += c * node_known[stencil[p]];
                for (int q = node_offsets[stencil[p]]; q < node_offsets[stencil[p] + 1]; ++q) {
                  const int col = node_cols[q];
                  if (marker[col] != row) {
                    marker[col] = row;
                    accumulator[col] = 0.0;
                    cols.push_back(col);
                  }
                  accumulator[col] += c * node_values[q];
                }
              }
              if (cols.empty()) continue;  // only fixed control points: a constant row
              std::sort(cols.begin(), cols.end());
              for (int col : cols) {
                out.row_cols.push_back(col);
                out.row_values.push_back(accumulator[col]);
                if (in_group[col] != group) {
                  in_group[col] = group;
                  union_cols.push_back(col);
                }
              }
              out.row_offsets.push_back(static_cast<int>(out.row_cols.size()));
              out.rhs.push_back(-known);
              ++row;
            }
        if (union_cols.empty()) continue;
        std::sort(union_cols.begin(), union_cols.end());
        out.group_cols.insert(out.group_cols.end(), union_cols.begin(), union_cols.end());
        out.group_offsets.push_back(static_cast<int>(out.group_cols.size()));
        out.block_offsets.push_back(row);
        ++group;
      }
  return out;
}
// IC(0) of A with the weak couplings |a_ij| < drop·sqrt(a_ii a_jj) removed: a CG preconditioner
// whose factorization stays cheap when refined T-splines make AᵀA rows long (hundreds of
// overlapping blending functions), at the price of a few more iterations.
// 0.05: more iterations but a much cheaper factorization; bunny_closed levels 2–3 solve in
// 0.31 s CPU against 0.44–0.53 s with 0.01 (0.58 s with 0.15), bimba about the same (1.4 vs 1.3 s).
constexpr double kPreconditionerDrop = 0.05;
class DroppedIncompleteCholesky {
 public:
  // a: the upper triangle with the diagonal first in each row (what solve_normal passes; the
  // CG reads only that triangle too). IC(0) reads a lower triangle: the kept entries are
  // transposed, which gives row j its columns i < j increasing and then the diagonal.
  void compute(const linalg::CsrMatrix& a) {
    const int n = a.rows();
    const auto& off = a.row_offsets();
    const auto& col = a.col_indices();
    const auto& val = a.values();
    std::vector<double> diag(n, 0.0);
    for (int i = 0; i < n; ++i) {
      assert(off[i] < off[i + 1] && col[off[i]] == i);
      diag[i] = std::abs(val[off[i]]);
    }
    auto keep = [&](int k, int i) { return std::abs(val[k]) >= drop_ * std::sqrt(diag[i] * diag[col[k]]); };
    std::vector<int> offsets(n + 1, 0);
    for (int i = 0; i < n; ++i) {
      ++offsets[i + 1];
      for (int k = off[i] + 1; k < off[i + 1]; ++k)
        if (keep(k, i)) ++offsets[col[k] + 1];
    }
    for (int i = 0; i < n; ++i) offsets[i + 1] += offsets[i];
    std::vector<int> fill(offsets.begin(), offsets.end() - 1), cols(offsets.back());
    std::vector<double> values(offsets.back());
    for (int i = 0; i < n; ++i) {
      cols[fill[i]] = i;
      values[fill[i]++] = val[off[i]];
      for (int k = off[i] + 1; k < off[i + 1]; ++k)
        if (keep(k, i)) {
          cols[fill[col[k]]] = i;
          values[fill[col[k]]++] = val[k];
        }
    }
    ic_.compute(linalg::CsrMatrix::from_arrays(n, a.cols(), std::move(offsets), std::move(cols),
                                               std::move(values)));
  }
  void solve(const double* r, double* z) const { ic_.solve(r, z); }
  void solve_block(int k, const double* const* r, double* const* z) const { ic_.solve_block(k, r, z); }

 private:
  double drop_ = kPreconditionerDrop;
  linalg::IncompleteCholesky0 ic_;
};

// The upper triangle of a (sorted rows holding their diagonal), the diagonal first in each row.
linalg::CsrMatrix upper_triangle(const linalg::CsrMatrix& a) {
  std::vector<int> offsets(1, 0), cols;
  std::vector<double> values;
  for (int i = 0; i < a.rows(); ++i) {
    for (int k = a.row_offsets()[i]; k < a.row_offsets()[i + 1]; ++k)
      if (a.col_indices()[k] >= i) {
        cols.push_back(a.col_indices()[k]);
        values.push_back(a.values()[k]);
      }
    offsets.push_back(static_cast<int>(cols.size()));
  }
  return linalg::CsrMatrix::from_arrays(a.rows(), a.cols(), std::move(offsets), std::move(cols), std::move(values));
}

// Solves (AᵀA + ε²I) x = Aᵀb + ε² prior for the unknown columns (the normal equations of
// min ‖A x − b‖² + ε²‖x − prior‖², ε² = regularization · mean diagonal of AᵀA) by CG from the
// current control points, and writes them back. ata: the upper triangle of AᵀA, the diagonal
// first in each row (GroupedGram::take_upper), all the CG and the preconditioner read.
TSplineFitResult solve_normal(TSpline& spline, const std::vector<int>& unknown_ids, linalg::CsrMatrix ata,
                              Eigen::MatrixXd atb, int rows, const Eigen::MatrixX3d& prior,
                              double regularization, double tolerance, int max_iterations) {
  const int n = static_cast<int>(unknown_ids.size());
  TSplineFitResult report;
  report.unknowns = n;
  if (n == 0) {
    report.converged = true;
    return report;
  }
  const std::vector<int>& off = ata.row_offsets();
  const std::vector<int>& col = ata.col_indices();
  std::vector<double>& val = ata.values();
  std::vector<int> diagonal(n, -1);
  double trace = 0.0;
  for (int r = 0; r < n; ++r)
    if (off[r] < off[r + 1] && col[off[r]] == r) {
      diagonal[r] = off[r];
      trace += val[off[r]];
    }
  const double mean = trace / n;
  const double eps2 = regularization * (mean > 0.0 ? mean : 1.0);
  for (int c = 0; c < n; ++c) {
    assert(diagonal[c] >= 0);
    val[diagonal[c]] += eps2;
    atb.row(c) += eps2 * prior.row(unknown_ids[c]);
  }
  report.rows = rows + n;
  Eigen::MatrixXd x0(n, 3);
  for (int c = 0; c < n; ++c) x0.row(c) = spline.points().row(unknown_ids[c]);
  linalg::ConjugateGradient<DroppedIncompleteCholesky> cg;
  cg.set_tolerance(tolerance);
  cg.set_max_iterations(max_iterations);
  cg.compute(ata);
  const Eigen::MatrixXd x = cg.solve(atb, x0);
  report.cg_iterations = cg.iterations();
  report.converged = cg.info() == linalg::SolverInfo::Success;
  Eigen::MatrixXd points = spline.points();
  for (int c = 0; c < n; ++c) points.row(unknown_ids[c]) = x.row(c);
  spline.set_points(points);
  return report;
}

// Solves min ‖A x − b‖² + ε‖x − prior‖² for the unknown columns and writes them back.
TSplineFitResult solve_stacked(TSpline& spline, const std::vector<int>& unknown_ids,
                               std::vector<linalg::Triplet>& triplets, Eigen::MatrixXd& rhs,
                               int rows, const Eigen::MatrixX3d& prior, double regularization,
                               double tolerance, int max_iterations) {
  const int n = static_cast<int>(unknown_ids.size());
  for (int c = 0; c < n; ++c) triplets.push_back({rows, c, 0.0});  // keeps the diagonal in the pattern
  const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(rows + 1, n, triplets);
  rhs.conservativeResize(rows + 1, 3);
  rhs.row(rows).setZero();
  linalg::NormalEquations normal = linalg::normal_equations(a, rhs);
  return solve_normal(spline, unknown_ids, upper_triangle(normal.ata), std::move(normal.atb), rows, prior,
                      regularization, tolerance, max_iterations);
}

// The sample rows of Eq. 3.5 (row s: w_i B_i(uvw_s) over the unknown columns, right side xyz_s
// minus the fixed functions' part), grouped by the knot-line cell holding them: all samples of
// a cell share its blending functions, so each cell is one dense Gram update (GroupedGram).
struct SampleBlocks {
  std::vector<std::pair<std::int64_t, int>> order;  // (cell, sample), sorted
  std::vector<int> begin, end;                      // range of `order` per block
  std::vector<int> slot_offsets{0}, slots;          // position in the cell's function list per column
  std::vector<int> group_offsets{0}, group_cols;    // unknown columns, increasing
};
SampleBlocks sample_blocks(const TSpline& spline, const Eigen::MatrixX3d& uvw, const std::vector<int>& column_of) {
  const Eigen::Index m = uvw.rows();
  SampleBlocks out;
  // Cell of each sample by the rule of TSpline's lookup (the last cell is closed).
  out.order.resize(m);
  for (Eigen::Index s = 0; s < m; ++s) {
    std::int64_t cell = 0, stride = 1;
    for (int a = 0; a < 3; ++a) {
      const std::vector<double>& lines = spline.knot_lines(a);
      const std::int64_t intervals = static_cast<std::int64_t>(lines.size()) - 1;
      std::int64_t k = std::upper_bound(lines.begin(), lines.end(), uvw(s, a)) - lines.begin() - 1;
      k = std::clamp<std::int64_t>(k, 0, intervals - 1);
      cell += k * stride;
      stride *= intervals;
    }
    out.order[s] = {cell, static_cast<int>(s)};
  }
  std::sort(out.order.begin(), out.order.end());
  std::vector<int> ids;
  std::vector<double> values;
  for (std::size_t b = 0; b < out.order.size();) {
    std::size_t e = b;
    while (e < out.order.size() && out.order[e].first == out.order[b].first) ++e;
    spline.basis_at(uvw.row(out.order[b].second).transpose(), {0, 0, 0}, ids, values);
    const std::size_t first = out.group_cols.size();
    for (std::size_t k = 0; k < ids.size(); ++k)
      if (column_of[ids[k]] >= 0) {
        out.slots.push_back(static_cast<int>(k));
        out.group_cols.push_back(column_of[ids[k]]);
      }
    assert(std::is_sorted(out.group_cols.begin() + static_cast<std::ptrdiff_t>(first), out.group_cols.end()));
    if (out.group_cols.size() > first) {
      out.begin.push_back(static_cast<int>(b));
      out.end.push_back(static_cast<int>(e));
      out.slot_offsets.push_back(static_cast<int>(out.slots.size()));
      out.group_offsets.push_back(static_cast<int>(out.group_cols.size()));
    }
    b = e;
  }
  return out;
}
}  // namespace

bool touches_exposed_face(const BlendingKnots& knots, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                          polycube::CubeFaceSet exposed) {
  for (int a = 0; a < 3; ++a) {
    const LocalKnots& r = knots[a];
    if (exposed.contains(2 * a) && r[0] == lo(a) && r[3] == lo(a)) return true;
    if (exposed.contains(2 * a + 1) && r[1] == hi(a) && r[4] == hi(a)) return true;
  }
  return false;
}

namespace {

// Eq. 3.5/3.6 (+ Eq. 4.7 fairing) for the control points ids (column_of: index → column or −1).
TSplineFitResult fit_columns(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                             const Eigen::MatrixX3d& prior, const std::vector<int>& ids,
                             const std::vector<int>& column_of, const TSplineFitOptions& options) {
  const int n = static_cast<int>(ids.size());
  const SampleBlocks samples = sample_blocks(spline, uvw, column_of);
  FairingRows fairing;
  if (options.smoothing > 0.0 && n > 0)
    fairing = laplacian_rows(spline, column_of, n, options.laplacian_nodes, std::sqrt(options.smoothing));
  // One pattern for both kinds of rows: the sample blocks' groups, then the fairing blocks'.
  const int sample_groups = static_cast<int>(samples.begin.size());
  std::vector<int> group_offsets = samples.group_offsets, group_cols = samples.group_cols;
  for (std::size_t g = 1; g < fairing.group_offsets.size(); ++g)
    group_offsets.push_back(fairing.group_offsets[g] + static_cast<int>(samples.group_cols.size()));
  group_cols.insert(group_cols.end(), fairing.group_cols.begin(), fairing.group_cols.end());
  GroupedGram gram(n, 3, std::move(group_offsets), std::move(group_cols));
  const int groups = gram.num_groups();
  std::vector<int> row_counts(static_cast<std::size_t>(groups));
  for (int g = 0; g < sample_groups; ++g) row_counts[g] = samples.end[g] - samples.begin[g];
  for (int g = sample_groups; g < groups; ++g)
    row_counts[g] = fairing.block_offsets[g - sample_groups + 1] - fairing.block_offsets[g - sample_groups];
  const int rows = std::accumulate(row_counts.begin(), row_counts.end(), 0);
  const Eigen::VectorXd& weights = spline.weights();
  const Eigen::MatrixXd& points = spline.points();
  gram.add_all(row_counts, [&](int g, Eigen::MatrixXd& block, Eigen::MatrixXd& rhs) {
    const int count = row_counts[g], k = gram.group_size(g);
    rhs.resize(count, 3);
    if (g < sample_groups) {
      const int* slot = samples.slots.data() + samples.slot_offsets[g];
      thread_local std::vector<int> ids_at;  // scratch: the callback may run on several threads
      thread_local std::vector<double> values;
      block.resize(count, k);
      for (int r = 0; r < count; ++r) {
        const int s = samples.order[samples.begin[g] + r].second;
        spline.basis_at(uvw.row(s).transpose(), {0, 0, 0}, ids_at, values);
        Eigen::RowVector3d known = Eigen::RowVector3d::Zero();
        for (std::size_t q = 0; q < ids_at.size(); ++q)
          if (column_of[ids_at[q]] < 0) known += (weights(ids_at[q]) * values[q]) * points.row(ids_at[q]);
        for (int c = 0; c < k; ++c) block(r, c) = weights(ids_at[slot[c]]) * values[slot[c]];
        rhs.row(r) = xyz.row(s) - known;
      }
      return;
    }
    // A fairing block: its rows' entries placed by their column's slot in the group's list.
    const int* cols = gram.group_columns(g);
    const int first = fairing.block_offsets[g - sample_groups];
    block.setZero(count, k);
    for (int r = 0; r < count; ++r) {
      for (int q = fairing.row_offsets[first + r]; q < fairing.row_offsets[first + r + 1]; ++q)
        block(r, std::lower_bound(cols, cols + k, fairing.row_cols[q]) - cols) = fairing.row_values[q];
      rhs.row(r) = fairing.rhs[first + r];
    }
  });
  Eigen::MatrixXd atb = std::move(gram.rhs());
  return solve_normal(spline, ids, gram.take_upper(), std::move(atb), rows, prior, options.regularization,
                      options.tolerance, options.max_iterations);
}
}  // namespace

TSplineFitResult fit_tspline(TSpline& spline, const Eigen::MatrixX3d& uvw,
                             const Eigen::MatrixX3d& xyz, const Eigen::MatrixX3d& prior,
                             const TSplineFitOptions& options) {
  assert(spline.dimension() == 3 && uvw.rows() == xyz.rows());
  const int n = spline.num_functions();
  std::vector<int> column_of(n), ids(n);
  for (int i = 0; i < n; ++i) column_of[i] = ids[i] = i;
  return fit_columns(spline, uvw, xyz, prior, ids, column_of, options);
}

TSplineFitResult fit_tspline_local(TSpline& spline, const Eigen::MatrixX3d& uvw,
                                   const Eigen::MatrixX3d& xyz, const Eigen::MatrixX3d& prior,
                                   const std::vector<int>& free_functions,
                                   const TSplineFitOptions& options) {
  assert(spline.dimension() == 3 && uvw.rows() == xyz.rows());
  std::vector<int> column_of(spline.num_functions(), -1);
  for (std::size_t c = 0; c < free_functions.size(); ++c) {
    assert(free_functions[c] >= 0 && free_functions[c] < spline.num_functions());
    assert(column_of[free_functions[c]] < 0);
    column_of[free_functions[c]] = static_cast<int>(c);
  }
  return fit_columns(spline, uvw, xyz, prior, free_functions, column_of, options);
}

TSplineFitResult fit_tspline_meshless(TSpline& spline, const Eigen::MatrixX3d& uvw,
                                      const Eigen::MatrixX3d& xyz, const Eigen::MatrixX3d& prior,
                                      const TSplineFitOptions& options) {
  assert(spline.dimension() == 3 && uvw.rows() == xyz.rows());
  const int n = spline.num_functions();
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  std::vector<int> boundary_column(n, -1), interior_column(n, -1), boundary_ids, interior_ids;
  for (int i = 0; i < n; ++i) {
    if (touches_exposed_face(spline.knots()[i], lo, hi, options.exposed_faces)) {
      boundary_column[i] = static_cast<int>(boundary_ids.size());
      boundary_ids.push_back(i);
    } else {
      interior_column[i] = static_cast<int>(interior_ids.size());
      interior_ids.push_back(i);
    }
  }
  // Step 1, Eq. 4.4/4.5: only boundary blending functions are non-zero on the surface samples.
  TSplineFitResult report;
  {
    RowBuilder builder{spline, boundary_column, {}, {}};
    std::vector<linalg::Triplet> triplets;
    Eigen::MatrixXd rhs(uvw.rows(), 3);
    int rows = 0;
    for (Eigen::Index s = 0; s < uvw.rows(); ++s) {
      Eigen::RowVector3d known = Eigen::RowVector3d::Zero();
      builder.add(uvw.row(s).transpose(), 1.0, rows, triplets, known);
      rhs.row(rows++) = xyz.row(s) - known;
    }
    report = solve_stacked(spline, boundary_ids, triplets, rhs, rows, prior,
                           options.regularization, options.tolerance, options.max_iterations);
  }
  // Step 2, Eq. 4.6/4.7: interior control points from the discrete Laplacian of F.
  {
    RowBuilder builder{spline, interior_column, {}, {}};
    std::vector<linalg::Triplet> triplets;
    std::vector<Eigen::RowVector3d> known;
    int rows = 0;
    add_laplacian_rows(builder, options.laplacian_nodes, 1.0, triplets, known, rows);
    Eigen::MatrixXd rhs(rows, 3);
    for (int r = 0; r < rows; ++r) rhs.row(r) = -known[r];
    const TSplineFitResult interior = solve_stacked(spline, interior_ids, triplets, rhs, rows, prior,
                                                    options.regularization, options.tolerance, options.max_iterations);
    report.cg_iterations = std::max(report.cg_iterations, interior.cg_iterations);
    report.converged = report.converged && interior.converged;
    report.rows += interior.rows;
    report.unknowns += interior.unknowns;
  }
  return report;
}

}  // namespace volspline::spline
