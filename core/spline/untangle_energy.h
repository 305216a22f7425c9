// SPDX-License-Identifier: MIT
// Internal to untangle_spline: the energy of one untangling pass over its free control points
// and its minimization.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/spline/node_jacobians.h"

namespace volspline::spline::detail {

/// The samples' terms, one array each: F(x) − xyz_s = offset_s + Σ_e x_{column_e} b_e over
/// e in start_s .. start_{s+1} − 1 (offset: the fixed functions' part minus the target).
/// normal: empty, or per sample a unit normal of the surface at a sample on it (zero elsewhere):
/// there the misfit's part along the surface is weighted by RegionEnergyOptions::tangent_weight.
struct SampleTerms {
  std::vector<Eigen::Vector3d> offset;
  std::vector<int> start{0}, column;
  std::vector<double> b;
  std::vector<Eigen::Vector3d> normal;
  int size() const { return static_cast<int>(offset.size()); }
};

/// The energy's nodes: J·S⁻¹ = fixed + rows(x) at node q (S⁻¹ = inverse_reference[q], the
/// inverse of the node's reference shape, already applied to fixed and to the rows).
struct Region {
  NodeJacobians rows;
  std::vector<Eigen::Matrix3d> fixed;
  std::vector<Eigen::Matrix3d> inverse_reference;
  Eigen::Vector3d mean_scale = Eigen::Vector3d::Zero();  ///< of the column norms of J
  /// Nodes that must end unfolded: the scanned ones and those not folded before. A folded node
  /// off the scan that the free functions cannot reach (bimba has some) would otherwise hold
  /// the ε continuation until its barrier dominates the energy.
  std::vector<char> guarded;
  /// Nodes on a cuboid edge (two coordinates on the domain boundary) are rows' fillers only:
  /// det J = 0 there wherever the surface is smooth across the edge (three tangents in a plane).
  /// held[q] is 0 for those, 1 for the energy's nodes.
  std::vector<char> held;
  /// Scattered nodes (the dense check's bad points of earlier passes), held by a hinge, not by
  /// the barrier (some cannot reach its margin): J = fixed + Σ_c x_c·g_cᵀ, g_c = w_c∇B_c there.
  std::vector<Eigen::Matrix3d> point_fixed;
  std::vector<double> point_scale;  ///< σ: |J e0||J e1||J e2| before the pass
  /// Per scattered node, the hinge's target instead of RegionEnergyOptions::hinge_target (a
  /// guard: no lower than it is now), or empty for that target at all of them.
  std::vector<double> point_target;
  /// Per scattered node, the factor on its hinge (a point standing for that many equal ones), or
  /// empty for 1 at all of them.
  std::vector<double> point_weight;
  /// Point e's (column, g) entries: point_columns/point_g[point_start[e] .. point_start[e+1]).
  std::vector<int> point_start{0}, point_columns;
  std::vector<Eigen::Vector3d> point_g;
};

/// Weights and stopping rule of minimize_region_energy.
struct RegionEnergyOptions {
  double data_scale = 0.0;     ///< weight of ‖F(uvw_s) − xyz_s‖² (1 / model units²)
  double tangent_weight = 1.0; ///< factor on the along-surface misfit of samples with a normal, [0, 1]
  double theta = 0.5;          ///< θ of param::foldover_free_energy, in [0, 1)
  double hinge_target = 0.02;  ///< τ of the scattered nodes' hinge (scaled Jacobian)
  int max_steps = 6;           ///< ε-continuation steps, ≥ 1
  int max_inner = 5;           ///< L-BFGS iterations per step, ≥ 1
  double stop_margin = 0.0;    ///< stop once every guarded node has det(J·S⁻¹) above this
};

/// Minimizes, over the free control points x (3 per free function, updated in place), the
/// barrier of Garanzha et al. 2021 (§3, with its ε continuation; the thesis has no untangling
/// step) at the region's held nodes, plus the hinge at its scattered nodes and the data term of
/// the samples. Returns the L-BFGS iterations.
int minimize_region_energy(const Region& region, const SampleTerms& samples, const RegionEnergyOptions& options,
                           Eigen::VectorXd& x);

}  // namespace volspline::spline::detail
