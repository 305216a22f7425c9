// SPDX-License-Identifier: MIT
// Internal to untangle_spline: one pass of the untangler (its nodes, seeds, free functions and
// energy) and the helpers it shares with untangle_spline's checks.
#pragma once

#include <array>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/spline/jacobian_certificate.h"
#include "core/spline/spline_untangling.h"
#include "core/spline/tspline.h"
#include "core/spline/untangle_energy.h"

namespace volspline::spline::detail {

/// Least share of |w∇B| at a point that the movable functions must carry for the point to be
/// worth untangling (bunny: seeds below 0.02 stay folded, those above 0.3 unfold).
constexpr double kMinMovableShare = 0.1;

/// The lattice of one pass, per axis: the nodes' parameters (ascending) and which are scanned.
struct AxisNodes {
  std::vector<double> t;
  std::vector<char> scanned;
};

/// The node Jacobians of the last pass, kept for the next one: the same nodes (passes differ in
/// rings only) and the spline as that pass left it need no second evaluation.
struct NodeCache {
  std::array<AxisNodes, 3> nodes;
  std::vector<Eigen::Matrix3d> jacobians;
  bool current = false;  ///< jacobians hold J at every node of `nodes` for the spline as it is
};

/// The nodes of a pass, per axis: nodes_per_knot_interval > 0: per interval of the spline's knot
/// lines, the centres of equal parts, as many as nodes_per_knot_interval and at least as many as
/// the interval holds steps of energy_stride/lattice (so coarse intervals keep the lattice's
/// density), all scanned; 0: the uniform lattice j/lattice (every energy_stride-th from j = 1,
/// every seed_stride-th scanned). Plus the boundary layers at boundary_layers[q] of the first
/// (last) node's distance from the face.
std::array<AxisNodes, 3> make_pass_nodes(const TSpline& spline, const SplineUntangleOptions& options);

/// The box the untangler works on: SplineUntangleOptions::region, or the spline's domain box.
Eigen::Vector3d region_min(const TSpline& spline, const SplineUntangleOptions& options);
Eigen::Vector3d region_max(const TSpline& spline, const SplineUntangleOptions& options);
/// The knot lines of axis a strictly inside the region, with the region's two ends.
std::vector<double> region_knot_lines(const TSpline& spline, const SplineUntangleOptions& options, int a);
/// True if a function must stay where it is: non-zero on an exposed face of the region (lo, hi),
/// or, with a region, its support not inside it.
bool held_function(const BlendingKnots& knots, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                   const SplineUntangleOptions& options);

/// S⁻¹ of a node's reference shape S: the node's own Jacobian where it is good (scaled Jacobian
/// ≥ 0.1: the energy is then least where the map already is), else an orthogonal frame of its
/// column lengths, each at least mean_scale (a folded column is short, e.g. bunny's faces' normal
/// derivative, and its own length would make a flat element the target).
Eigen::Matrix3d inverse_reference_shape(const Eigen::Matrix3d& jacobian, const Eigen::Vector3d& mean_scale);

/// The certificate rounds' stopping rule: they stop when no cell is uncertified, after
/// max_rounds rounds, or when the uncertified count has not fallen for kPatience + 1 rounds;
/// the points of the round with the fewest are kept.
class CertificateRounds {
 public:
  static constexpr int kPatience = 2;
  /// Records round `round` (uncertified cells, the spline's points then); true if the rounds
  /// stop. final_uncertified() is then the fewest, and best_points() the points to keep.
  bool stop(int round, int uncertified, const Eigen::MatrixXd& points, int max_rounds);
  int stalled() const { return stalled_; }  ///< rounds since the count last fell
  int final_uncertified() const { return best_; }
  /// The points of the round with the fewest.
  const Eigen::MatrixXd& best_points() const { return best_points_; }
  /// The points of the round with the fewest (moved out).
  Eigen::MatrixXd take_best_points() { return std::move(best_points_); }

 private:
  int best_ = std::numeric_limits<int>::max(), stalled_ = 0;
  Eigen::MatrixXd best_points_;
};

/// RegionEnergyOptions of a pass from the untangler's options; step: one length unit of the data
/// term in model units.
RegionEnergyOptions region_energy_options(const SplineUntangleOptions& options, double step, double tangent_weight);

/// Lexicographic order of parameter points (u, then v, then w): the held points' order.
bool lexicographic_less(const Eigen::Vector3d& p, const Eigen::Vector3d& q);
/// Adds the points `more` to the held points (sorted by lexicographic_less), without repeats.
void merge_points(std::vector<Eigen::Vector3d>& held, std::vector<Eigen::Vector3d> more);
/// Where one uncertified cell of spline folds, in uvw: its certificate's lowest corner and the
/// points of a 3×3×3 grid on the closed cell with det J < 0 (a point on the cell's face keeps
/// the face's coordinate exactly).
std::vector<Eigen::Vector3d> uncertified_points(const TSpline& spline, const UncertifiedCell& u, double below = 0.0);

/// The functions' w·∂B/∂u_a at one parameter point (TSpline::basis_at with derivative order 1 per
/// axis); the three lists hold the same functions in the same order.
struct PointGradients {
  std::array<std::vector<int>, 3> ids;
  std::array<std::vector<double>, 3> values;
  /// Evaluates them at p.
  void at(const TSpline& spline, const Eigen::Vector3d& p);
  /// Σ |w∇B| over the functions (*total) and over those for which movable(f) holds (returned),
  /// summed in function order.
  template <class Movable>
  double movable_share(const TSpline& spline, Movable&& movable, double* total) const {
    double sum = 0.0, moved = 0.0;
    for (std::size_t q = 0; q < ids[0].size(); ++q) {
      const int f = ids[0][q];
      const double g = spline.weights()(f) * Eigen::Vector3d(values[0][q], values[1][q], values[2][q]).norm();
      sum += g;
      if (movable(f)) moved += g;
    }
    *total = sum;
    return moved;
  }
};

/// Where a pass's seeds come from.
enum class PassSeeds {
  ScanAndPoints,  ///< the scanned nodes below min_scaled_jacobian, plus `points`; scan after
  PointsOnly,     ///< `points` alone; nodes evaluated only in the box of the free functions'
                  ///< supports, no scan (the result's scan fields stay 0)
};

/// One scan of `nodes` for seeds and one untangling of the points near them (see
/// untangle_spline); the moved control points are written to spline. points: parameter points
/// that seed at their nearest node and are held by the hinge (the dense checks' bad points);
/// held: more points held by the hinge where the free functions reach them, seeding nothing.
/// tangent_weight < 1: samples on a domain face weigh their misfit along the surface (normal:
/// the cross product of the spline's tangents there) by it (RegionEnergyOptions).
/// cache: the node Jacobians carried from pass to pass. Precondition: as untangle_spline.
SplineUntangleResult untangle_pass(TSpline& spline, const std::array<AxisNodes, 3>& nodes, const Eigen::MatrixX3d& uvw,
                                   const Eigen::MatrixX3d& xyz, const std::vector<Eigen::Vector3d>& points,
                                   const SplineUntangleOptions& options, PassSeeds seeds, NodeCache& cache,
                                   const std::vector<Eigen::Vector3d>& held = {}, double tangent_weight = 1.0);

}  // namespace volspline::spline::detail
