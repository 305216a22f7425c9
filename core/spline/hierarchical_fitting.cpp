// SPDX-License-Identifier: MIT
#include "core/spline/hierarchical_fitting.h"

#include <algorithm>
#include <utility>

namespace volspline::spline {

const char* fit_stop_reason_name(FitStopReason reason) {
  switch (reason) {
    case FitStopReason::Target: return "target";
    case FitStopReason::Budget: return "budget";
    case FitStopReason::Diminishing: return "diminishing";
    case FitStopReason::MaxLevels: return "max_levels";
    case FitStopReason::NoCells: return "no_cells";
  }
  return "unknown";
}

HierarchicalFitResult run_hierarchical_fitting(HierarchicalFit& fit, MarkingRule& marking) {
  for (int level = 0;; ++level) {
    fit.fit(level);
    if (const std::optional<FitStopReason> reason = marking.stop(level)) return {*reason, level};
    Marking marked = marking.mark(level);
    if (marked.cells.empty()) return {marked.empty_reason, level};
    const int before = fit.num_control_points();
    bool accepted = false;
    while (!marked.cells.empty()) {
      std::vector<int> cells = marked.cells;
      std::sort(cells.begin(), cells.end());
      if (fit.refine(cells, level)) {
        marking.refined(cells.size(), before, fit.num_control_points());
        accepted = true;
        break;
      }
      if (marking.over_budget() == OverBudget::Stop) break;
      // marked.cells is ranked: keep the worse half.
      marked.cells.resize(marked.cells.size() / 2);
    }
    if (!accepted) return {FitStopReason::Budget, level};
  }
}

void BudgetedBulkMarking::refined(std::size_t cells, int before, int after) {
  growth_per_cell_ = std::max(1.0, static_cast<double>(after - before)) / static_cast<double>(cells);
}

Marking BudgetedBulkMarking::mark_within_budget(std::vector<int> candidates, const std::vector<double>& error,
                                                double total, double fraction, double room) const {
  bool over_budget = false;
  Marking marking;
  marking.cells = bulk_mark(std::move(candidates), error, total, fraction, room, growth_per_cell_, &over_budget);
  marking.empty_reason = over_budget ? FitStopReason::Budget : FitStopReason::NoCells;
  return marking;
}

std::vector<int> bulk_mark(std::vector<int> candidates, const std::vector<double>& error, double total,
                           double fraction, double room, double growth_per_cell, bool* over_budget) {
  *over_budget = false;
  std::sort(candidates.begin(), candidates.end(),
            [&](int a, int b) { return error[a] != error[b] ? error[a] > error[b] : a < b; });
  std::vector<int> marked;
  double covered = 0.0;
  for (int id : candidates) {
    if (covered >= fraction * total) break;
    marked.push_back(id);
    covered += error[id];
  }
  if (!marked.empty() && growth_per_cell > 0.0) {
    const std::size_t affordable = static_cast<std::size_t>(std::max(0.0, 0.9 * room / growth_per_cell));
    if (affordable == 0) {
      *over_budget = true;
      marked.clear();
    } else if (marked.size() > affordable) {
      marked.resize(affordable);
    }
  }
  return marked;
}

}  // namespace volspline::spline
