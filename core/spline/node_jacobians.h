// SPDX-License-Identifier: MIT
// Internal to untangle_spline: the Jacobians at the energy's nodes as a fixed linear map of the
// free control points.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace volspline::spline::detail {

/// A free function on a lattice of nodes: the box of nodes where it may be non-zero, first[a] ..
/// first[a] + count[a] − 1 per axis, and the factors of w·∇B there: w·N_a and w·N_a' per axis
/// (the weight folded into axis 0), so w·∇B = (n'₀n₁n₂, n₀n'₁n₂, n₀n₁n'₂).
struct FreeFunction {
  std::array<int, 3> first{}, count{};
  std::array<std::vector<double>, 3> value, slope;
};

/// The Jacobians at the region nodes as a fixed linear map of the free control points (the
/// knots do not change while untangling): per node, the free functions non-zero there and their
/// w·∇B (compressed rows), so J(node) = fixed + Σ_c x_c·(w∇B_c)ᵀ sums in registers, and the
/// energy's gradient scatters back through the same rows in the same sweep. The row entries are
/// stored in single precision (sums in double): the sweeps' memory traffic counts, and the
/// rounding only perturbs the search's model of how J changes with x, not J itself (the fixed
/// part is made with the same rows, so J at the start point is exact, and the spline is
/// evaluated anew after the pass). Where the CPU has AVX2 the sweeps run in
/// node_jacobians_avx2.cpp with the same bits.
class NodeJacobians {
 public:
  NodeJacobians() = default;
  /// Rows from the functions' node boxes; node_index: lattice node → region node (−1: none),
  /// sizes: lattice nodes per axis, num_nodes: region nodes. Columns ascend within a row.
  NodeJacobians(const std::vector<FreeFunction>& functions, const std::vector<int>& node_index,
                std::array<int, 3> sizes, std::size_t num_nodes);
  /// Rows given whole (nodes anywhere, e.g. in several cuboids): node q's entries are
  /// start[q] .. start[q + 1] − 1, each a column (ascending within a row) and its w∇B.
  NodeJacobians(std::vector<int> start, std::vector<int> column, const std::vector<Eigen::Vector3d>& gradient);

  /// The free control points x (3 per column) padded to 4 per column (the 4th is 0), as the
  /// sweeps read them and write gradients: one 4-lane load or store per entry.
  static void pad(const Eigen::VectorXd& x, std::vector<double>& x4);
  /// The inverse of pad: x keeps its size, its entries come from x4.
  static void unpad(const std::vector<double>& x4, Eigen::VectorXd& x);

  /// Σ_c x_c·(w∇B_c)ᵀ at node q; x4: padded (see pad).
  Eigen::Matrix3d linear(const double* x4, std::size_t q) const;
  /// Rows of node q times s (J·s = fixed·s + Σ_c x_c·(sᵀ w∇B_c)ᵀ): the energy then sees J·S⁻¹.
  void transform(std::size_t q, const Eigen::Matrix3d& s);
  /// gradient_c += d·g_c(q) for the functions at node q (g: w∇B, or S⁻ᵀw∇B after transform;
  /// d = ∂E/∂J, or ∂E/∂(J·S⁻¹)); gradient4: padded (see pad).
  void add_gradient(const Eigen::Matrix3d& d, std::size_t q, double* gradient4) const;

 private:
  std::vector<int> start_, column_;
  std::vector<float> gradient_;  // w∇B (S⁻ᵀw∇B after transform), 3 per entry
  [[maybe_unused]] bool avx2_ = false;  // the CPU runs the AVX2 sweeps (builds without them never read it)
};

/// Σ_e x_{column[e]}·g_eᵀ over entries begin .. end − 1 (scattered points' rows, g_e in double
/// precision: gradient[3e .. 3e + 2]); x4: the free control points padded (NodeJacobians::pad).
/// Sums in entry order (AVX2 where the CPU has it, the same bits).
Eigen::Matrix3d scattered_linear(const int* column, const double* gradient, int begin, int end, const double* x4);

}  // namespace volspline::spline::detail
