// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Cholesky>

#include "core/linalg/csr_matrix.h"

namespace volspline::linalg {

/// Smoothed-aggregation algebraic multigrid preconditioner (Vaněk, Mandel & Brezina 1996):
/// z = M⁻¹ r is one symmetric V-cycle, so M is SPD and fits ConjugateGradient.
///
/// Hierarchy (compute): strong couplings |a_ij| ≥ θ·√(a_ii a_jj) (θ = 0.08, halved per level);
/// greedy aggregates of a node and its strong neighbours (then leftovers joined to their
/// strongest aggregated neighbour, then grouped among themselves); the piecewise-constant
/// tentative prolongator smoothed by one damped Jacobi step on the filtered matrix (weak
/// couplings lumped into the diagonal), ω = 4 / (3 ρ̄) with ρ̄ the Gershgorin bound of D⁻¹A
/// (tight for Laplacians: 2); coarse matrices Pᵀ A P (symmetrized), coarsening until at most
/// kCoarseSize unknowns, which are solved by a dense LDLᵀ. Cycle: one forward Gauss–Seidel
/// sweep, coarse correction, one backward sweep.
/// For graph Laplacians with Dirichlet rows (harmonic and Tutte maps) the CG iteration count
/// stays about constant as the mesh is refined, where IC(0)'s grows like √n: the solve costs
/// O(n). Deterministic (sequential, fixed order). The work arrays of a V-cycle are members:
/// one object must not run two solves concurrently.
class AlgebraicMultigrid {
 public:
  /// Matrices this small are one dense level (M = A exactly).
  static constexpr int kCoarseSize = 256;

  /// Builds the hierarchy of the square symmetric matrix a (both triangles stored, positive
  /// diagonal; an M-matrix such as a Dirichlet graph Laplacian coarsens best).
  void compute(const CsrMatrix& a);

  /// z = M⁻¹ r for n entries (raw arrays); r and z may alias.
  void solve(const double* r, double* z) const;

  /// solve for k columns at once (r[c] → z[c]), streaming each level's matrices once for up to
  /// 4 of them; each column's result is bit-identical to solve's. r[c] and z[c] may alias.
  void solve_block(int k, const double* const* r, double* const* z) const;

  /// Returns M⁻¹ r; r has n entries.
  Eigen::VectorXd solve(const Eigen::VectorXd& r) const;

  /// Levels including the dense coarsest one (1 when n ≤ kCoarseSize).
  int num_levels() const { return static_cast<int>(levels_.size()) + 1; }
  /// Unknowns of level l (0 = the matrix of compute).
  int level_size(int level) const;
  /// Σ nnz(A_l) / nnz(A_0) over all levels (the dense coarsest counted as n²).
  double operator_complexity() const;

 private:
  struct Level {
    CsrMatrix a;                       // n_l × n_l
    Eigen::VectorXd inverse_diagonal;  // 1 / a_ii
    CsrMatrix prolongation;            // n_l × n_{l+1}
  };
  template <int K>
  void cycle(int level, const double* const* b, double* const* x) const;
  template <int K>
  void solve_k(const double* const* r, double* const* z) const;

  std::vector<Level> levels_;            // all but the coarsest
  Eigen::LDLT<Eigen::MatrixXd> coarse_;  // the coarsest level
  int coarse_size_ = 0;
  int coarse_nnz_ = 0;
  // Per level l ≥ 1 (index l − 1): right-hand side and solution, 4 columns of n_l entries.
  mutable std::vector<Eigen::MatrixXd> b_, x_;
  mutable Eigen::MatrixXd input_;  // copies of r when r and z alias
};

}  // namespace volspline::linalg
