// SPDX-License-Identifier: MIT
#include "core/spline/tspline_fitting.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <utility>

#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"


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

// Normal equations of the Eq. 4.7 rows scale·(F(u_g) − (1/6) Σ_nbr F(u_j)) at the interior
// nodes g of a uniform grid, over the unknown columns (the fixed functions' part moves to the
// right side). The basis is evaluated once per grid node and the rows are built sorted.
struct FairingNormal {
  linalg::CsrMatrix ata;  // n×n, sorted rows
  Eigen::MatrixXd atb;    // n×3
  int rows = 0;
};
FairingNormal laplacian_normal_equations(const TSpline& spline, const std::vector<int>& column_of, int n,
                                         int nodes_requested, double scale) {
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  std::array<int, 3> nodes;
  for (int a = 0; a < 3; ++a) nodes[a] = automatic_nodes(spline, a, nodes_requested);
  auto node_id = [&](int i, int j, int k) { return i + nodes[0] * (j + nodes[1] * k); };
  // Basis at every grid node: unknown columns with w_i B_i, and the fixed part of F.
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
  // Rows (sorted columns), skipping rows without unknowns.
  std::vector<int> row_offsets(1, 0), row_cols;
  std::vector<double> row_values;
  std::vector<Eigen::RowVector3d> rhs;
  std::vector<double> accumulator(n, 0.0);
  std::vector<int> marker(n, -1), cols;
  int rows = 0;
  for (int k = 1; k + 1 < nodes[2]; ++k)
    for (int j = 1; j + 1 < nodes[1]; ++j)
      for (int i = 1; i + 1 < nodes[0]; ++i) {
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
            if (marker[col] != rows) {
              marker[col] = rows;
              accumulator[col] = 0.0;
              cols.push_back(col);
            }
            accumulator[col] += c * node_values[q];
          }
        }
        if (cols.empty()) continue;  // only fixed control points: a constant row
        std::sort(cols.begin(), cols.end());
        for (int col : cols) {
          row_cols.push_back(col);
          row_values.push_back(accumulator[col]);
        }
        row_offsets.push_back(static_cast<int>(row_cols.size()));
        rhs.push_back(-known);
        ++rows;
      }
  Eigen::MatrixXd b(rows, 3);
  for (int r = 0; r < rows; ++r) b.row(r) = rhs[r];
  const linalg::CsrMatrix a = linalg::CsrMatrix::from_arrays(rows, n, std::move(row_offsets), std::move(row_cols),
                                                             std::move(row_values));
  linalg::NormalEquations normal = linalg::normal_equations(a, b);
  FairingNormal out;
  out.ata = std::move(normal.ata);
  out.atb = std::move(normal.atb);
  out.rows = rows;
  return out;
}

// IC(0) of A with the weak couplings |a_ij| < drop·sqrt(a_ii a_jj) removed: a CG preconditioner
// whose factorization stays cheap when refined T-splines make AᵀA rows long (hundreds of
// overlapping blending functions), at the price of a few more iterations.
// 0.01: on bunny_closed level 4, 64 instead of 22 CG iterations, 5× less time in the solve.
constexpr double kPreconditionerDrop = 0.01;
class DroppedIncompleteCholesky {
 public:
  void compute(const linalg::CsrMatrix& a) {
    const int n = a.rows();
    const auto& off = a.row_offsets();
    const auto& col = a.col_indices();
    const auto& val = a.values();
    std::vector<double> diag(n, 0.0);
    for (int i = 0; i < n; ++i)
      for (int k = off[i]; k < off[i + 1]; ++k)
        if (col[k] == i) diag[i] = std::abs(val[k]);
    std::vector<int> offsets(1, 0), cols;
    std::vector<double> values;
    for (int i = 0; i < n; ++i) {
      for (int k = off[i]; k < off[i + 1]; ++k) {
        const int j = col[k];
        if (j == i || std::abs(val[k]) >= drop_ * std::sqrt(diag[i] * diag[j])) {
          cols.push_back(j);
          values.push_back(val[k]);
        }
      }
      offsets.push_back(static_cast<int>(cols.size()));
    }
    ic_.compute(linalg::CsrMatrix::from_arrays(n, a.cols(), std::move(offsets), std::move(cols),
                                               std::move(values)));
  }
  void solve(const double* r, double* z) const { ic_.solve(r, z); }

 private:
  double drop_ = kPreconditionerDrop;
  linalg::IncompleteCholesky0 ic_;
};

// Solves (AᵀA + ε²I) x = Aᵀb + ε² prior for the unknown columns (the normal equations of
// min ‖A x − b‖² + ε²‖x − prior‖², ε² = regularization · mean diagonal of AᵀA) by CG from the
// current control points, and writes them back. ata must hold the diagonal in its pattern.
TSplineFitReport solve_normal(TSpline& spline, const std::vector<int>& unknown_ids, linalg::CsrMatrix ata,
                              Eigen::MatrixXd atb, int rows, const Eigen::MatrixX3d& prior,
                              double regularization, double tolerance, int max_iterations) {
  const int n = static_cast<int>(unknown_ids.size());
  TSplineFitReport report;
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
    for (int k = off[r]; k < off[r + 1]; ++k)
      if (col[k] == r) {
        diagonal[r] = k;
        trace += val[k];
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
TSplineFitReport solve_stacked(TSpline& spline, const std::vector<int>& unknown_ids,
                               std::vector<linalg::Triplet>& triplets, Eigen::MatrixXd& rhs,
                               int rows, const Eigen::MatrixX3d& prior, double regularization,
                               double tolerance, int max_iterations) {
  const int n = static_cast<int>(unknown_ids.size());
  for (int c = 0; c < n; ++c) triplets.push_back({rows, c, 0.0});  // keeps the diagonal in the pattern
  const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(rows + 1, n, triplets);
  rhs.conservativeResize(rows + 1, 3);
  rhs.row(rows).setZero();
  linalg::NormalEquations normal = linalg::normal_equations(a, rhs);
  return solve_normal(spline, unknown_ids, std::move(normal.ata), std::move(normal.atb), rows, prior,
                      regularization, tolerance, max_iterations);
}

// Sum of two n×n matrices with sorted rows (the pattern is the union).
linalg::CsrMatrix add_matrices(const linalg::CsrMatrix& a, const linalg::CsrMatrix& b) {
  const int n = a.rows();
  std::vector<int> offsets(1, 0), cols;
  std::vector<double> values;
  cols.reserve(a.nnz() + b.nnz() / 2);
  values.reserve(a.nnz() + b.nnz() / 2);
  const auto& ao = a.row_offsets();
  const auto& ac = a.col_indices();
  const auto& av = a.values();
  const auto& bo = b.row_offsets();
  const auto& bc = b.col_indices();
  const auto& bv = b.values();
  for (int r = 0; r < n; ++r) {
    int i = ao[r], j = bo[r];
    while (i < ao[r + 1] || j < bo[r + 1]) {
      if (j == bo[r + 1] || (i < ao[r + 1] && ac[i] < bc[j])) {
        cols.push_back(ac[i]);
        values.push_back(av[i++]);
      } else if (i == ao[r + 1] || bc[j] < ac[i]) {
        cols.push_back(bc[j]);
        values.push_back(bv[j++]);
      } else {
        cols.push_back(ac[i]);
        values.push_back(av[i++] + bv[j++]);
      }
    }
    offsets.push_back(static_cast<int>(cols.size()));
  }
  return linalg::CsrMatrix::from_arrays(n, n, std::move(offsets), std::move(cols), std::move(values));
}

// Normal equations AᵀA, Aᵀb of the sample rows of Eq. 3.5 (row s: w_i B_i(uvw_s) over the
// unknown columns, right side xyz_s minus the fixed functions' part). The samples are grouped
// by the knot-line cell holding them: all samples of a cell share its blending functions, so
// each cell adds one small dense Gram matrix (a few hundred samples share a cell's functions
// on refined splines, far cheaper than one sparse outer product per sample).
struct SampleNormal {
  linalg::CsrMatrix ata;  // n×n, the diagonal always in the pattern
  Eigen::MatrixXd atb;    // n×3
  int rows = 0;
};
SampleNormal sample_normal_equations(const TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                                     const std::vector<int>& column_of, int n) {
  const Eigen::Index m = uvw.rows();
  // Cell of each sample by the rule of TSpline's lookup (the last cell is closed).
  std::vector<std::pair<std::int64_t, int>> order(m);
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
    order[s] = {cell, static_cast<int>(s)};
  }
  std::sort(order.begin(), order.end());
  struct Block {
    int begin, end;          // range of `order`
    std::vector<int> slot;   // position in the cell's function list of each unknown column
    std::vector<int> cols;   // unknown columns, increasing
  };
  std::vector<Block> blocks;
  std::vector<int> ids;
  std::vector<double> values;
  for (std::size_t b = 0; b < order.size();) {
    std::size_t e = b;
    while (e < order.size() && order[e].first == order[b].first) ++e;
    spline.basis_at(uvw.row(order[b].second).transpose(), {0, 0, 0}, ids, values);
    Block block{static_cast<int>(b), static_cast<int>(e), {}, {}};
    for (std::size_t k = 0; k < ids.size(); ++k)
      if (column_of[ids[k]] >= 0) {
        block.slot.push_back(static_cast<int>(k));
        block.cols.push_back(column_of[ids[k]]);
      }
    assert(std::is_sorted(block.cols.begin(), block.cols.end()));
    if (!block.cols.empty()) blocks.push_back(std::move(block));
    b = e;
  }
  // Pattern: row r couples with the columns of every block holding r (and itself).
  std::vector<int> holder_offsets(n + 1, 0);
  for (const Block& block : blocks)
    for (int c : block.cols) ++holder_offsets[c + 1];
  for (int c = 0; c < n; ++c) holder_offsets[c + 1] += holder_offsets[c];
  std::vector<int> holders(holder_offsets.back()), fill(holder_offsets.begin(), holder_offsets.end() - 1);
  for (std::size_t b = 0; b < blocks.size(); ++b)
    for (int c : blocks[b].cols) holders[fill[c]++] = static_cast<int>(b);
  std::vector<int> offsets(n + 1, 0), pattern;
  std::vector<int> marker(n, -1);
  std::vector<int> row_cols;
  for (int r = 0; r < n; ++r) {
    row_cols.assign(1, r);
    marker[r] = r;
    for (int h = holder_offsets[r]; h < holder_offsets[r + 1]; ++h)
      for (int c : blocks[holders[h]].cols)
        if (marker[c] != r) {
          marker[c] = r;
          row_cols.push_back(c);
        }
    std::sort(row_cols.begin(), row_cols.end());
    pattern.insert(pattern.end(), row_cols.begin(), row_cols.end());
    offsets[r + 1] = static_cast<int>(pattern.size());
  }
  std::vector<int> diagonal(n);
  for (int r = 0; r < n; ++r) diagonal[r] = static_cast<int>(std::lower_bound(pattern.begin() + offsets[r], pattern.begin() + offsets[r + 1], r) - pattern.begin());
  SampleNormal out;
  std::vector<double> ata_values(pattern.size(), 0.0);
  out.atb = Eigen::MatrixXd::Zero(n, 3);
  Eigen::MatrixXd rows_b, gram;
  Eigen::MatrixX3d rhs_b;
  const Eigen::VectorXd& weights = spline.weights();
  const Eigen::MatrixXd& points = spline.points();
  for (const Block& block : blocks) {
    const int count = block.end - block.begin, k = static_cast<int>(block.cols.size());
    rows_b.resize(count, k);
    rhs_b.resize(count, 3);
    for (int r = 0; r < count; ++r) {
      const int s = order[block.begin + r].second;
      spline.basis_at(uvw.row(s).transpose(), {0, 0, 0}, ids, values);
      Eigen::RowVector3d known = Eigen::RowVector3d::Zero();
      for (std::size_t q = 0; q < ids.size(); ++q)
        if (column_of[ids[q]] < 0) known += (weights(ids[q]) * values[q]) * points.row(ids[q]);
      for (int c = 0; c < k; ++c) {
        const int q = block.slot[c];
        rows_b(r, c) = weights(ids[q]) * values[q];
      }
      rhs_b.row(r) = xyz.row(s) - known;
    }
    out.rows += count;
    gram.noalias() = rows_b.transpose() * rows_b;
    out.atb(block.cols, Eigen::all) += rows_b.transpose() * rhs_b;
    // Scatter the upper triangle: block.cols is a sorted subset of every row's sorted pattern,
    // so each row is walked once from its diagonal.
    for (int a = 0; a < k; ++a) {
      int p = diagonal[block.cols[a]];
      const double* g = gram.col(a).data();
      for (int c = a; c < k; ++c) {
        while (pattern[p] != block.cols[c]) ++p;
        ata_values[p] += g[c];
      }
    }
  }
  // Mirror: rows in increasing order meet the lower entries of each row in increasing order.
  std::vector<int> next_lower(offsets.begin(), offsets.end() - 1);
  for (int r = 0; r < n; ++r)
    for (int p = diagonal[r] + 1; p < offsets[r + 1]; ++p) ata_values[next_lower[pattern[p]]++] = ata_values[p];
  out.ata = linalg::CsrMatrix::from_arrays(n, n, std::move(offsets), std::move(pattern), std::move(ata_values));
  return out;
}

}  // namespace

bool touches_domain_boundary(const BlendingKnots& knots, const Eigen::Vector3d& lo,
                             const Eigen::Vector3d& hi) {
  for (int a = 0; a < 3; ++a) {
    const LocalKnots& r = knots[a];
    if (r[0] == lo(a) && r[3] == lo(a)) return true;
    if (r[1] == hi(a) && r[4] == hi(a)) return true;
  }
  return false;
}

namespace {

// Eq. 3.5/3.6 (+ Eq. 4.7 fairing) for the control points ids (column_of: index → column or −1).
TSplineFitReport fit_columns(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                             const Eigen::MatrixX3d& prior, const std::vector<int>& ids,
                             const std::vector<int>& column_of, const TSplineFitOptions& options) {
  const int n = static_cast<int>(ids.size());
  SampleNormal normal = sample_normal_equations(spline, uvw, xyz, column_of, n);
  int rows = normal.rows;
  if (options.smoothing > 0.0 && n > 0) {
    const FairingNormal fairing =
        laplacian_normal_equations(spline, column_of, n, options.laplacian_nodes, std::sqrt(options.smoothing));
    normal.ata = add_matrices(normal.ata, fairing.ata);
    normal.atb += fairing.atb;
    rows += fairing.rows;
  }
  return solve_normal(spline, ids, std::move(normal.ata), std::move(normal.atb), rows, prior,
                      options.regularization, options.tolerance, options.max_iterations);
}

}  // namespace

TSplineFitReport fit_tspline(TSpline& spline, const Eigen::MatrixX3d& uvw,
                             const Eigen::MatrixX3d& xyz, const Eigen::MatrixX3d& prior,
                             const TSplineFitOptions& options) {
  assert(spline.dimension() == 3 && uvw.rows() == xyz.rows());
  const int n = spline.num_functions();
  std::vector<int> column_of(n), ids(n);
  for (int i = 0; i < n; ++i) column_of[i] = ids[i] = i;
  return fit_columns(spline, uvw, xyz, prior, ids, column_of, options);
}

TSplineFitReport fit_tspline_local(TSpline& spline, const Eigen::MatrixX3d& uvw,
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

TSplineFitReport fit_tspline_meshless(TSpline& spline, const Eigen::MatrixX3d& uvw,
                                      const Eigen::MatrixX3d& xyz, const Eigen::MatrixX3d& prior,
                                      const TSplineFitOptions& options) {
  assert(spline.dimension() == 3 && uvw.rows() == xyz.rows());
  const int n = spline.num_functions();
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  std::vector<int> boundary_column(n, -1), interior_column(n, -1), boundary_ids, interior_ids;
  for (int i = 0; i < n; ++i) {
    if (touches_domain_boundary(spline.knots()[i], lo, hi)) {
      boundary_column[i] = static_cast<int>(boundary_ids.size());
      boundary_ids.push_back(i);
    } else {
      interior_column[i] = static_cast<int>(interior_ids.size());
      interior_ids.push_back(i);
    }
  }
  // Step 1, Eq. 4.4/4.5: only boundary blending functions are non-zero on the surface samples.
  TSplineFitReport report;
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
    const TSplineFitReport interior = solve_stacked(spline, interior_ids, triplets, rhs, rows, prior,
                                                    options.regularization, options.tolerance, options.max_iterations);
    report.cg_iterations = std::max(report.cg_iterations, interior.cg_iterations);
    report.converged = report.converged && interior.converged;
    report.rows += interior.rows;
    report.unknowns += interior.unknowns;
  }
  return report;
}

}  // namespace volspline::spline
