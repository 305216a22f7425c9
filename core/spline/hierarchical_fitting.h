// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

namespace volspline::spline {

/// Why hierarchical fitting stopped refining.
enum class FitStopReason {
  Target,       ///< the error reached its target
  Budget,       ///< the next level would exceed the control point budget
  Diminishing,  ///< the last level gained too little (AdaptiveDensityOptions::min_gain_rate, min_decrease_rel)
  MaxLevels,    ///< the maximum number of levels was done
  NoCells,      ///< no cell may be split or no error is left to mark
};

/// Stable lower-case name of a stop reason ("target", "budget", "diminishing", "max_levels",
/// "no_cells"), the value of the stats key stop_reason.
const char* fit_stop_reason_name(FitStopReason reason);

/// The fit policy of run_hierarchical_fitting: owns the spline, its refinement hierarchy and the samples. Cell ids
/// are the fit's own (RefinementGrid leaf ids for one patch; a multi-patch fit, one TSpline per
/// cuboid, numbers the cells of all its patches and splits each patch's share).
class HierarchicalFit {
 public:
  virtual ~HierarchicalFit() = default;
  /// Fits the control points of the current spline and measures its error (FittingError(g));
  /// `level` counts the refinements done (0 first).
  virtual void fit(int level) = 0;
  /// Control points of the current spline.
  virtual int num_control_points() const = 0;
  /// Splits `cells` (increasing ids, all marked at `level`) into 8 each by knot insertion. True:
  /// the refined spline is current and fit(level + 1) follows. False: the refinement exceeds the
  /// control point budget and the fit is left as it was.
  virtual bool refine(const std::vector<int>& cells, int level) = 0;
};

/// Cells to split at one level, or why there are none.
struct Marking {
  /// Cell ids in decreasing priority: a refinement over budget may be retried with a prefix.
  std::vector<int> cells;
  FitStopReason empty_reason = FitStopReason::NoCells;  ///< why, when `cells` is empty
};

/// What run_hierarchical_fitting does when a refinement exceeds the control point budget.
enum class OverBudget {
  Stop,          ///< stop with the current spline
  HalveMarking,  ///< retry with the first half of the marked cells; stop when none is left
};

/// The marking policy of run_hierarchical_fitting: decides from the errors the fit measured whether to go on and
/// which cells to split. It reads the fit's measures through its own reference to the fit.
class MarkingRule {
 public:
  virtual ~MarkingRule() = default;
  /// After fit(level): why to stop, or nothing to refine towards level + 1.
  virtual std::optional<FitStopReason> stop(int level) = 0;
  /// The cells to split towards level + 1.
  virtual Marking mark(int level) = 0;
  /// A refinement of `cells` marked cells was accepted: from `before` to `after` control points.
  virtual void refined(std::size_t cells, int before, int after) {}
  /// What to do with a refinement over budget.
  virtual OverBudget over_budget() const = 0;
};

/// A marking rule built on bulk_mark that learns the control points a split cell adds from the
/// last accepted refinement and retries a refinement over budget with the worse half.
class BudgetedBulkMarking : public MarkingRule {
 public:
  void refined(std::size_t cells, int before, int after) override;
  OverBudget over_budget() const override { return OverBudget::HalveMarking; }

 protected:
  /// bulk_mark of `candidates` within `room` more control points; empty: Budget if nothing was
  /// affordable, else NoCells.
  Marking mark_within_budget(std::vector<int> candidates, const std::vector<double>& error, double total,
                             double fraction, double room) const;

 private:
  double growth_per_cell_ = 0.0;  // control points added per split cell at the last level; 0 = unknown
};

/// How run_hierarchical_fitting ended.
struct HierarchicalFitResult {
  FitStopReason stop_reason = FitStopReason::MaxLevels;
  int levels = 0;  ///< refinements done; the last fit was fit(levels)
};

/// Algorithm 4 (§4.3.3), hierarchical fitting: fit level 0, then until the marking rule stops
/// (or marks nothing, or a refinement over budget cannot be shrunk): mark the cells whose error is
/// too large, split them, refit. The fit and the marking rule are the policies; this loop is the
/// only place the algorithm's control flow is written.
HierarchicalFitResult run_hierarchical_fitting(HierarchicalFit& fit, MarkingRule& marking);

/// Bulk (Dörfler) marking of one refinement level (the thesis's "cells over the threshold",
/// made scale-free): `candidates` sorted by decreasing `error` (ties by increasing id), the first
/// of them until `fraction` of `total` is covered, then cut to the cells the budget affords
/// (0.9·room/growth_per_cell; growth_per_cell ≤ 0 = no estimate yet, no cut). Empty when nothing
/// is marked or nothing is affordable; *over_budget tells the latter.
std::vector<int> bulk_mark(std::vector<int> candidates, const std::vector<double>& error, double total,
                           double fraction, double room, double growth_per_cell, bool* over_budget);

}  // namespace volspline::spline
