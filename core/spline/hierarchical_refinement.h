// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/spline/tspline.h"

namespace volspline::spline {

/// The cells of hierarchical fitting (run_hierarchical_fitting, §3.5.1, §4.3.3): a uniform grid of
/// boxes over a parameter domain, each of which can be split into 8 children, recursively.
class RefinementGrid {
 public:
  /// Uniform cells[a] boxes along axis a over [lo, hi]. Asserts cells ≥ 1 and lo < hi.
  RefinementGrid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::array<int, 3> cells);

  /// Ids of the current leaf cells, increasing.
  std::vector<int> leaves() const;
  int num_leaves() const { return num_leaves_; }
  /// Lower and upper parameter corners and level (0 = initial grid) of cell `id`.
  const Eigen::Vector3d& cell_min(int id) const { return nodes_[id].lo; }
  const Eigen::Vector3d& cell_max(int id) const { return nodes_[id].hi; }
  int cell_level(int id) const { return nodes_[id].level; }
  /// Deepest level of any leaf.
  int max_level() const { return max_level_; }
  /// Leaf containing uvw (closed at the domain's upper faces); uvw is clamped into the domain.
  int leaf_of(const Eigen::Vector3d& uvw) const;

  /// Splits the given leaves into 8 (the `Subdivision` step of run_hierarchical_fitting) and returns `spline` refined
  /// (§4.3.3): every blending function whose ray-traced knot vector R* in the new T-mesh has
  /// knots its own R lacks is split by knot insertion (Table 4.1, Eq. 4.8/4.9), repeatedly,
  /// which keeps F and Σ w_i B_i unchanged. Knots of R that R* lacks are kept (the thesis
  /// would add T-mesh vertices for them; the point-based spline needs no such bookkeeping).
  /// Asserts every id is a leaf. `acceleration` is that of the returned spline.
  TSpline split(const TSpline& spline, const std::vector<int>& leaf_ids,
                TSplineAcceleration acceleration = TSplineAcceleration::Auto);

  /// Blending functions as plain arrays: knots n, weights n, points n×D (D in 1..4, as TSpline).
  struct Functions {
    std::vector<BlendingKnots> knots;
    Eigen::VectorXd weights;
    Eigen::MatrixXd points;
  };
  /// split() without building a TSpline (no evaluation grid): for fits that only need the
  /// knots, e.g. on a tensor grid of samples. Same functions, order and points as split().
  Functions split_functions(const Functions& functions, const std::vector<int>& leaf_ids);

  /// Ray-traced knot vector R* (§4.2.2) along `axis` from the anchor (knots[a][2] per axis) of a
  /// blending function in the current cells: the two nearest cell faces on each side touching
  /// the ray; the domain ends repeat as boundary knots (§4.3.1).
  LocalKnots ray_knots(const BlendingKnots& knots, int axis) const;

 private:
  void collect_planes(int id, int axis, const Eigen::Vector3d& anchor, std::vector<double>& planes) const;
  // Sorted distinct positions along `axis` of the cell faces the line through anchor meets.
  std::vector<double> line_planes(int axis, const Eigen::Vector3d& anchor) const;
  // R* from the planes of the anchor's line and the anchor coordinate `centre` along axis.
  LocalKnots knots_on_line(const std::vector<double>& planes, int axis, double centre) const;

  struct Node {
    Eigen::Vector3d lo, hi;
    int level = 0;
    int first_child = -1;  // children first_child .. first_child + 7, index c = i + 2j + 4k
  };
  Eigen::Vector3d lo_, hi_;
  std::array<int, 3> cells_;
  std::vector<Node> nodes_;  // the first cells_[0]·cells_[1]·cells_[2] are the roots
  int num_leaves_ = 0;
  int max_level_ = 0;
};

}  // namespace volspline::spline
