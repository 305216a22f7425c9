// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "core/spline/bspline_basis.h"

namespace volspline::spline {

class BsplineVolume;

/// Local knot vectors along u, v, w of one blending function B_i = N_u(u) N_v(v) N_w(w) (Eq. 4.2).
using BlendingKnots = std::array<LocalKnots, 3>;

/// Hash of knot vectors for unordered containers: equal knots (0.0 and −0.0 alike) hash equal.
/// Only lookups may depend on it, never an output order.
struct KnotsHash {
  std::size_t operator()(const LocalKnots& knots) const;
  std::size_t operator()(const BlendingKnots& knots) const;
};

/// Which formula TSpline evaluation uses.
enum class TSplineForm {
  SemiStandard,  ///< F = Σ w_i p_i B_i (Eq. 4.3); equals Eq. 4.1 when Σ w_i B_i ≡ 1. No division.
  Rational,      ///< F = Σ w_i p_i B_i / Σ w_i B_i (Eq. 4.1).
};

/// How TSpline evaluates inside a cell of its knot-line grid (results agree to rounding).
enum class TSplineAcceleration {
  Auto,              ///< CellPolynomials if they fit in 256 MiB, else FunctionLists.
  CellPolynomials,   ///< per cell, F's numerator and Σ w_i B_i as tricubic power-form polynomials:
                     ///< 64·(D+1) doubles per cell, evaluation cost independent of the overlap.
  FunctionLists,     ///< per cell, the list of overlapping blending functions: O(overlap) per
                     ///< evaluation, memory O(Σ_i #cells in the support of B_i).
};

/// Point-based trivariate cubic T-spline (thesis §3.5, §4.2.2): blending function i has three
/// 5-knot local vectors knots()[i], a weight w_i > 0 and a control point p_i in R^D (D in 1..4:
/// 3 for geometry, 4 for geometry + density).
///
/// One patch: the domain is a box, per axis [min_i r0, max_i r4] over all blending functions,
/// closed at both ends. A blending function whose r4 is the domain end is evaluated with
/// RightEnd::Closed, all others with RightEnd::Open (see bspline_basis.h), so the domain is
/// closed at its last knot. A union of boxes (an L of three blocks) is not a TSpline: its box
/// holds points where F = 0 and Σ w_i B_i = 0. A multi-cuboid solid is one TSpline per cuboid
/// plus the gluing graph (the shape of G+Smo's gsMultiPatch); which faces of a patch's box lie
/// on the solid's surface is a polycube::CubeFaceSet the fits and the untangler take
/// (TSplineFitOptions::exposed_faces, touches_exposed_face), never guessed from the box.
///
/// Acceleration: the constructor builds the knot-line grid (cells between consecutive distinct
/// knot values per axis); inside a cell every univariate basis function is one cubic polynomial,
/// stored once per (knot vector, cell interval) in power form on the cell's local coordinate.
/// Each cell lists its overlapping blending functions, so an evaluation is one binary search per
/// axis plus O(#functions overlapping the cell); memory O(Σ_i #cells in the support of B_i).
/// Since F is one tricubic polynomial per cell, the cells can also store F (and Σ w_i B_i)
/// directly in power form (TSplineAcceleration::CellPolynomials), which is faster when the grid
/// is small enough. Evaluation is const and thread-safe.
class TSpline {
 public:
  /// Builds the spline and its acceleration grid. knots has n entries, weights n, points n×D.
  /// Throws volspline::Error naming the blending function if a knot vector is not finite,
  /// decreasing or of zero length (r0 = r4), a weight is not finite and positive, a point is not
  /// finite; also if n = 0, sizes disagree, D is not in 1..4, or the grid would exceed 2^26 cells.
  /// CellPolynomials is honoured whatever the memory it takes.
  TSpline(std::vector<BlendingKnots> knots, Eigen::VectorXd weights, Eigen::MatrixXd points,
          TSplineAcceleration acceleration = TSplineAcceleration::Auto);

  /// Number n of blending functions (= control points).
  int num_functions() const { return static_cast<int>(knots_.size()); }
  /// Number D of components of F.
  int dimension() const { return dimension_; }
  /// Knot vectors of every blending function.
  const std::vector<BlendingKnots>& knots() const { return knots_; }
  /// n weights w_i.
  const Eigen::VectorXd& weights() const { return weights_; }
  /// n×D control points p_i.
  const Eigen::MatrixXd& points() const { return points_; }
  /// Replaces the control points (same n×D shape) keeping knots, weights and the grid, e.g. after
  /// a refit. Throws volspline::Error if the shape differs or an entry is not finite.
  void set_points(Eigen::MatrixXd points);

  /// Lower domain corner (u, v, w).
  Eigen::Vector3d domain_min() const { return {breaks_[0].front(), breaks_[1].front(), breaks_[2].front()}; }
  /// Upper domain corner (u, v, w).
  Eigen::Vector3d domain_max() const { return {breaks_[0].back(), breaks_[1].back(), breaks_[2].back()}; }
  /// Sorted distinct knot values along axis a (the knot lines of the acceleration grid).
  const std::vector<double>& knot_lines(int axis) const { return breaks_[axis]; }
  /// Number of cells of the acceleration grid.
  int num_cells() const { return static_cast<int>(cells_.size()); }
  /// Largest number of blending functions overlapping one cell.
  int max_functions_per_cell() const { return max_functions_per_cell_; }
  /// True if evaluation uses per-cell polynomials (see TSplineAcceleration).
  bool has_cell_polynomials() const { return !cell_numerator_.empty(); }
  /// Switches to TSplineAcceleration::CellPolynomials if they fit in the memory Auto allows
  /// (256 MiB; no-op if already there): for a spline about to be evaluated on many lattices
  /// (untangling, measures). Evaluation then agrees with before to rounding. Returns
  /// has_cell_polynomials().
  bool use_cell_polynomials();

  /// F(uvw) in the given form, written to value[0..D). No allocation.
  /// Throws volspline::Error if uvw is outside the domain or not finite. Rational form:
  /// precondition Σ w_i B_i > 0 at uvw.
  void evaluate_to(const Eigen::Vector3d& uvw, TSplineForm form, double* value) const;
  /// F(uvw), D values. Throws like evaluate_to.
  Eigen::VectorXd evaluate(const Eigen::Vector3d& uvw, TSplineForm form = TSplineForm::SemiStandard) const;
  /// F(uvw) and the D×3 Jacobian [∂F/∂u ∂F/∂v ∂F/∂w] written column-major
  /// (jacobian[d + D·a] = ∂F_d/∂uvw_a); the rational form uses the quotient rule. No allocation.
  /// Throws like evaluate_to.
  void evaluate_with_jacobian(const Eigen::Vector3d& uvw, TSplineForm form, double* value,
                              double* jacobian) const;
  /// D×3 Jacobian at uvw (3×3 for geometry). Throws like evaluate_to.
  Eigen::MatrixXd jacobian(const Eigen::Vector3d& uvw, TSplineForm form = TSplineForm::SemiStandard) const;
  /// Partial derivative ∂^(o0+o1+o2) / ∂u^o0 ∂v^o1 ∂w^o2 of the semi-standard form Σ w_i p_i B_i,
  /// D values; orders >= 0 (orders > 3 give 0). Throws like evaluate_to.
  Eigen::VectorXd derivative(const Eigen::Vector3d& uvw, const std::array<int, 3>& order) const;
  /// The semi-standard F = Σ w_i p_i B_i (Eq. 4.3) and its D×3 Jacobian at every point
  /// (u[i], v[j], w[k]) of the tensor lattice coords = {u, v, w} (each axis non-decreasing, inside
  /// the domain), cell by cell: inside one knot-line cell every B_i is a product of fixed
  /// univariate pieces, so the sums run as a tensor-product pass (u, then v, then w) instead of
  /// one lookup and one pass over the cell's functions per point. visit(i, j, k, value, jacobian)
  /// is called once per point (value[0..D), jacobian column-major as in evaluate_with_jacobian),
  /// in cell order. Agrees with evaluate_with_jacobian to rounding. Throws like evaluate_to if a
  /// coordinate is outside the domain.
  void evaluate_lattice_with_jacobian(
      const std::array<std::vector<double>, 3>& coords,
      const std::function<void(int i, int j, int k, const double* value, const double* jacobian)>& visit) const;
  /// Σ w_i B_i(uvw): 1 everywhere for a semi-standard spline. Throws like evaluate_to.
  double weight_sum(const Eigen::Vector3d& uvw) const;
  /// F at each row of uvw (m×3), returns m×D. The rows are evaluated grouped by knot cell (a
  /// stable radix sort of their cell ids), so a cell's polynomial or function list is read once
  /// per group instead of once per row: a large spline's cell data need not stay in cache. Each
  /// row has the bits of evaluate_to. Throws like evaluate_to, naming the row.
  Eigen::MatrixXd evaluate_batch(const Eigen::MatrixX3d& uvw, TSplineForm form = TSplineForm::SemiStandard) const;
  /// As evaluate_batch, into values (resized to m×D; kept if already that size, so a caller
  /// evaluating many batches reuses its storage).
  void evaluate_batch(const Eigen::MatrixX3d& uvw, TSplineForm form, Eigen::MatrixXd& values) const;
  /// F and its Jacobian at each row of uvw (m×3), grouped by cell as evaluate_batch: values is
  /// resized to m×D, jacobians to m×3D (kept if already that size) with row i = the column-major D×3 Jacobian of
  /// evaluate_with_jacobian (jacobians(i, d + D·a) = ∂F_d/∂uvw_a), with its bits. Throws like
  /// evaluate_to, naming the row.
  void evaluate_batch_with_jacobian(const Eigen::MatrixX3d& uvw, TSplineForm form, Eigen::MatrixXd& values,
                                    Eigen::MatrixXd& jacobians) const;

  /// Blending functions whose support contains uvw: their indices (increasing) and the partial
  /// derivative of the given order of B_i (unweighted; order (0,0,0) is B_i itself). Functions of
  /// the cell whose value is exactly zero are listed too. For least-squares fitting.
  /// Throws like evaluate_to.
  void basis_at(const Eigen::Vector3d& uvw, const std::array<int, 3>& order,
                std::vector<int>& function_ids, std::vector<double>& values) const;
  /// basis_at for the three first derivatives at once (orders (1,0,0), (0,1,0), (0,0,1), with
  /// their bits): one cell lookup and one set of piece values for all three. Throws like
  /// evaluate_to.
  void basis_gradient_at(const Eigen::Vector3d& uvw, std::vector<int>& function_ids,
                         std::array<std::vector<double>, 3>& gradient) const;
  /// Index in [0, num_cells()) of the knot-line cell holding uvw, by the rule evaluation uses
  /// (along each axis [b_k, b_k+1), the last interval closed). Every point of one cell has the
  /// same basis_at list (cell_functions), so least-squares samples can be grouped by cell.
  /// Throws like evaluate_to.
  int cell_of(const Eigen::Vector3d& uvw) const;
  /// Grid interval of cell (0 <= cell < num_cells()) along u, v, w: the cell is the box
  /// [knot_lines(a)[k_a], knot_lines(a)[k_a + 1]] per axis a. Cells are numbered u fastest.
  std::array<int, 3> cell_index(int cell) const;
  /// The cell's polynomials in power form on its local coordinates s ∈ [0, 1]³ (s_a = (uvw_a −
  /// b_a)/(b'_a − b_a) on the cell box [b, b']): numerator[m·D + d] of Σ w_i p_i B_i and
  /// denominator[m] of Σ w_i B_i for the monomial m = (4a + b)·4 + c of s_u^a s_v^b s_w^c.
  /// Exact to rounding of the knot-vector pieces (each cell of Eq. 4.3 is one tricubic
  /// polynomial); from the cell polynomials if present, else summed from the cell's functions.
  /// Precondition: 0 <= cell < num_cells(); numerator holds 64·D, denominator 64 doubles.
  void cell_power_form(int cell, double* numerator, double* denominator) const;
  /// Blending functions overlapping cell (0 <= cell < num_cells()), increasing: the list basis_at
  /// gives at every point of the cell. function_ids is resized.
  void cell_functions(int cell, std::vector<int>& function_ids) const;
  /// B_i(uvw) from its knot vectors directly (no grid), 0 outside the support; for tests and
  /// single queries. Precondition: 0 <= i < n.
  double blending_function(int i, const Eigen::Vector3d& uvw) const;

 private:
  struct Cell {
    std::uint32_t entry_begin = 0;
    std::uint32_t entry_end = 0;
    std::uint32_t piece_begin = 0;  // num_pieces[0] u pieces, then v, then w
    std::uint16_t num_pieces[3] = {0, 0, 0};
  };
  struct Entry {
    std::uint32_t function = 0;
    std::uint16_t piece[3] = {0, 0, 0};  // local index into the cell's u, v, w pieces
  };

  // Values (derivative order per axis) of the univariate pieces of uvw's cell, u then v then w;
  // a stack buffer unless the cell has more pieces.
  struct PieceValues {
    static constexpr int kStack = 192;
    double stack[kStack];
    std::vector<double> heap;
    const double* axis[3] = {nullptr, nullptr, nullptr};
  };
  const Cell& piece_values(const Eigen::Vector3d& uvw, const std::array<int, 3>& order, PieceValues& out) const;

  // build_grid in its steps: the knot-line breaks and lookup bins per axis, the shared power-form
  // pieces (per function: first interval and first piece per axis), the cells' function entries
  // (returns the CSR offsets), and each cell's distinct pieces.
  void build_grid();
  void build_breaks();
  void build_pieces(std::array<std::vector<int>, 3>& first_cell, std::array<std::vector<int>, 3>& first_piece);
  std::vector<std::uint64_t> build_cell_entries(const std::array<std::vector<int>, 3>& first_cell);
  void build_cell_pieces(const std::array<std::vector<int>, 3>& first_cell,
                         const std::array<std::vector<int>, 3>& first_piece, const std::vector<std::uint64_t>& counts);
  void build_cell_polynomials();
  int locate(const Eigen::Vector3d& uvw, double* local, int* k) const;
  template <int D, bool kRational, bool kJacobian>
  void evaluate_impl(const Eigen::Vector3d& uvw, double* value, double* jacobian) const;
  // Rows [begin, end) of a batch grouped by knot cell: position j holds row[j] with its cell and
  // local coordinates (3 per position); rows of one cell in increasing order. The buffers are
  // reused from chunk to chunk.
  struct SortedRows {
    std::vector<std::uint32_t> cell, row, count, next_cell, next_row, rank;
    std::vector<double> local, next_local;
  };
  // Throws like evaluate_to, naming the row.
  void sort_rows(const Eigen::MatrixX3d& uvw, Eigen::Index begin, Eigen::Index end, SortedRows& sorted) const;
  template <int D, bool kRational, bool kJacobian>
  void evaluate_at(int cell, const double* s, const int* k, double* value, double* jacobian) const;
  // Writes `channels` = D (or 4D with the Jacobian) doubles per sorted position to out.
  template <int D, bool kRational, bool kJacobian>
  void evaluate_sorted(const SortedRows& sorted, double* out) const;
  // The batch's rows chunk by chunk: sorted, evaluated (D or 4D doubles per sorted position), then
  // scatter(begin, end, sorted, results) writes rows [begin, end) out.
  template <bool kJacobian, class Scatter>
  void evaluate_chunks(const Eigen::MatrixX3d& uvw, TSplineForm form, Scatter&& scatter) const;
  template <int D>
  void evaluate_lattice_impl(const std::array<std::vector<double>, 3>& coords,
                             const std::function<void(int, int, int, const double*, const double*)>& visit) const;
  template <int D, bool kRational, bool kJacobian>
  void evaluate_polynomial(int cell, const double* s, const int* k, double* value, double* jacobian) const;

  int dimension_ = 0;
  std::vector<BlendingKnots> knots_;
  Eigen::VectorXd weights_;
  Eigen::MatrixXd points_;
  std::vector<double> weighted_points_;  // n×D row-major w_i p_i
  std::array<std::vector<double>, 3> breaks_;
  std::array<std::vector<double>, 3> inverse_widths_;
  std::array<std::vector<int>, 3> bin_first_;  // grid interval containing each uniform bin's start
  std::array<double, 3> bin_scale_{};          // bins per unit parameter
  std::array<std::vector<std::array<double, 4>>, 3> pieces_;  // power form in s ∈ [0, 1]
  std::vector<Cell> cells_;
  std::vector<std::uint32_t> cell_pieces_;
  std::vector<Entry> entries_;
  int max_functions_per_cell_ = 0;
  // Per cell, monomial m = (4·a + b)·4 + c of s_u^a s_v^b s_w^c: D numerator coefficients
  // (Σ w p B) and one denominator coefficient (Σ w B). Empty unless CellPolynomials is used.
  std::vector<double> cell_numerator_;
  std::vector<double> cell_denominator_;
  // The CPU runs the AVX2 Horner passes (same bits as the portable ones); builds without them
  // never read it.
  [[maybe_unused]] bool avx2_ = false;
};

/// The T-spline of a full tensor grid: one blending function per control point of the volume,
/// with the local knot vectors cut from its clamped global knots (so the replicated end knots act
/// as the boundary knots of §4.3.1), weight 1 and the same control point. Equal to the volume
/// everywhere and semi-standard. Function index = volume.control_index(i0, i1, i2).
TSpline from_bspline_volume(const BsplineVolume& volume,
                            TSplineAcceleration acceleration = TSplineAcceleration::Auto);

}  // namespace volspline::spline
