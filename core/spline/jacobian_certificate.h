// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/spline/bezier_extraction.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Number of Bernstein coefficients of det J on one cell: degree (8, 8, 8), 9³.
constexpr int kJacobianCoefficients = 729;

/// The Bernstein coefficients of det ∂F/∂s on a geometric Bézier cell (D = 3), s ∈ [0, 1]³ the
/// cell's local coordinates: det J is x_s0 · (x_s1 × x_s2), a product of the three derivative
/// nets (degrees (2,3,3), (3,2,3), (3,3,2)), so a polynomial of degree (8, 8, 8); the products are
/// formed exactly in the scaled Bernstein basis C(n, i) t^i (1 − t)^(n − i) (where a product is a
/// plain convolution), no sampling. coefficient (i, j, k) at i + 9j + 81k. det ∂F/∂uvw is this
/// divided by the cell's three widths. Also returns, in column_bound, an upper bound of
/// |x_s0|·|x_s1|·|x_s2| over the cell (the product of the largest derivative-net norms; the
/// derivative is in the convex hull of its net). Precondition: cell.dimension == 3.
void jacobian_determinant_bernstein(const BezierCell& cell, double* coefficients, double* column_bound);

/// Outcome of certifying one cell.
enum class JacobianCellStatus {
  Certified,  ///< every Bernstein coefficient of det J on every leaf box is ≥ −τ: no fold
  Negative,   ///< det J < −τ at a leaf box corner (an exact value): a fold is proven
  Undecided,  ///< some coefficient < −τ at the depth limit, no negative value found
};

/// Options of the certificate; checked on entry (volspline::Error).
struct JacobianCertificateOptions {
  /// Binary de Casteljau splits (at 1/2, cycling through u, v, w) at most per cell, [0, 24].
  /// Only boxes whose lowest coefficient is below −τ with no negative corner are split, so a
  /// certified or proven-negative cell stops early (a GPC spline takes 24: gpc_certificate_options).
  int max_depth = 12;
  /// Rounding allowance τ: coefficients ≥ −rounding_rel·U count as non-negative, U the cell's
  /// column_bound, in [0, 1e-6]. The coefficients carry rounding of order 1e-15·U; an exactly
  /// degenerate edge (det J = 0 along a cuboid edge) must not fail on it.
  double rounding_rel = 1e-12;
};

/// Certificate of one cell.
struct JacobianCellBound {
  JacobianCellStatus status = JacobianCellStatus::Certified;
  /// Lower bound (to rounding) of det ∂F/∂uvw over the closed cell, whatever the status: the
  /// smallest coefficient over the final boxes of the subdivision, divided by the cell widths.
  double det_j_lower_bound = 0;
  /// det_j_lower_bound scaled like the scaled Jacobian: the smallest coefficient divided by U.
  /// For a Certified cell a lower bound of det J / (|J_u||J_v||J_w|) over the cell, in [0, 1].
  double det_j_lower_bound_rel = 0;
  int leaves = 1;  ///< leaf boxes of the subdivision
  /// Local coordinates s ∈ [0, 1]³ of the lowest det J found at a corner of a box the search
  /// visited (exact values: a box's corner coefficients are det J there), and that value scaled
  /// like det_j_lower_bound_rel. Where a cell is not Certified this is where to unfold it.
  Eigen::Vector3d lowest_corner_s = Eigen::Vector3d::Zero();
  double lowest_corner_rel = 0;
};

/// Certifies det J ≥ 0 on one geometric Bézier cell (DESIGN §6; thesis Eq. 4.3 makes every cell
/// one tricubic polynomial): the degree-(8, 8, 8) Bernstein coefficients of det J bound it from
/// below on the cell (non-negative basis, partition of unity); where the lowest coefficient is
/// negative but the box's corner values (exact) are not, the box is split by de Casteljau at 1/2
/// and both halves are checked, up to options.max_depth splits. What a Certified cell means
/// exactly: det J ≥ −τ everywhere on the closed cell (τ = rounding_rel·U, the allowance for
/// rounding in the coefficients), so no point of the cell, its faces, edges or corners is folded;
/// det J may be 0 on the cell's boundary, e.g. along a cuboid edge where the boundary surface is
/// smooth (the cube's right angle maps to a flat angle), but never below −τ. Precondition:
/// cell.dimension == 3; options valid.
JacobianCellBound certify_bezier_cell(const BezierCell& cell, const JacobianCertificateOptions& options);

/// A cell that is not Certified.
struct UncertifiedCell {
  int cuboid = 0;  ///< the patch's id as given to certify_jacobian
  int cell = 0;    ///< TSpline cell id
  Eigen::Vector3d uvw_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d uvw_max = Eigen::Vector3d::Zero();
  JacobianCellBound bound;
};

/// Certificate of a whole single-patch spline (a multi-cuboid spline certifies each cuboid's
/// TSpline and merges with merge_certificates).
struct JacobianCertificate {
  int cells = 0;
  int certified_cells = 0;
  /// certified_cells / cells (1 for an empty spline).
  double jacobian_certified_fraction = 1;
  /// smallest det_j_lower_bound_rel over all cells (negative if a cell is not certified).
  double det_j_lower_bound_rel = 1;
  std::vector<double> cell_bound_rel;     ///< per TSpline cell, det_j_lower_bound_rel
  std::vector<UncertifiedCell> uncertified;  ///< in (cuboid, cell) order
};

/// The certify_bezier_cell results of the last call per (cuboid, cell), for calls on a spline
/// whose control points move between them (the untangler's certificate rounds): a cell whose
/// Bézier coefficients and box are bit for bit those stored takes the stored bound, the same bits
/// as certifying it again (most cells lie outside the moved functions' supports). Stored results
/// are dropped when the options change. Not for concurrent use.
class JacobianCertificateCache {
 public:
  /// The bound of certify_bezier_cell(cell, options) for (cuboid, cell.cell): stored or computed
  /// (and stored).
  JacobianCellBound certify(int cuboid, const BezierCell& cell, const JacobianCertificateOptions& options);

 private:
  struct Entry {
    bool valid = false;
    std::array<double, 64 * 3> points{};
    Eigen::Vector3d uvw_min = Eigen::Vector3d::Zero(), uvw_max = Eigen::Vector3d::Zero();
    JacobianCellBound bound;
  };
  std::vector<std::vector<Entry>> entries_;  // per cuboid, per cell id
  JacobianCertificateOptions options_;
};

/// certify_bezier_cell on every cell of a geometric spline (D = 3). Throws volspline::Error if
/// the dimension is not 3 or options are invalid.
JacobianCertificate certify_jacobian(const TSpline& spline, const JacobianCertificateOptions& options = {},
                                     int cuboid = 0);

/// certify_jacobian on the cells inside the box [box_min, box_max] only (to 1e-9 of its size),
/// e.g. a GPC patch's cuboid box (its cells beyond a Continued face are the neighbour's);
/// cell_bound_rel then lists those cells in cell order. cache (or null): cells unchanged since
/// its last call take its results (the same certificate). Throws like certify_jacobian.
JacobianCertificate certify_jacobian_in_box(const TSpline& spline, const Eigen::Vector3d& box_min,
                                            const Eigen::Vector3d& box_max,
                                            const JacobianCertificateOptions& options = {}, int cuboid = 0,
                                            JacobianCertificateCache* cache = nullptr);

}  // namespace volspline::spline
