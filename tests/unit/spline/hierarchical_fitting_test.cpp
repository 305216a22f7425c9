// SPDX-License-Identifier: MIT
#include "core/spline/hierarchical_fitting.h"

#include <doctest/doctest.h>

using namespace volspline;

namespace {

// A fit over 1D "cells" 0..n−1: splitting a cell adds 7 control points; the error of a level is
// 1/(level + 1). The marking rule marks cells 0..k−1 and records what the loop did.
class CountingFit final : public spline::HierarchicalFit, public spline::MarkingRule {
 public:
  CountingFit(int budget, int marked, spline::OverBudget policy) : budget_(budget), marked_(marked), policy_(policy) {}
  void fit(int level) override { fitted.push_back(level); }
  int num_control_points() const override { return points_; }
  bool refine(const std::vector<int>& cells, int) override {
    tried.push_back(static_cast<int>(cells.size()));
    if (points_ + 7 * static_cast<int>(cells.size()) > budget_) return false;
    points_ += 7 * static_cast<int>(cells.size());
    return true;
  }
  std::optional<spline::FitStopReason> stop(int level) override {
    if (level >= 3) return spline::FitStopReason::MaxLevels;
    return std::nullopt;
  }
  spline::Marking mark(int) override {
    spline::Marking m;
    for (int c = marked_ - 1; c >= 0; --c) m.cells.push_back(c);  // ranked, not sorted
    return m;
  }
  void refined(std::size_t cells, int before, int after) override { growth.push_back((after - before) / int(cells)); }
  spline::OverBudget over_budget() const override { return policy_; }

  std::vector<int> fitted, tried, growth;

 private:
  int points_ = 8;
  const int budget_, marked_;
  const spline::OverBudget policy_;
};

}  // namespace

TEST_CASE("Algorithm 4 loop: fit, stop, mark, refine, refit until the marking rule stops") {
  CountingFit f(1000, 2, spline::OverBudget::Stop);
  const spline::HierarchicalFitResult r = spline::run_hierarchical_fitting(f, f);
  CHECK(r.stop_reason == spline::FitStopReason::MaxLevels);
  CHECK(r.levels == 3);
  CHECK(f.fitted == std::vector<int>{0, 1, 2, 3});
  CHECK(f.tried == std::vector<int>{2, 2, 2});
  CHECK(f.growth == std::vector<int>{7, 7, 7});
  CHECK(f.num_control_points() == 8 + 3 * 14);
}

TEST_CASE("Algorithm 4 loop: a refinement over budget stops, or is retried with the worse half") {
  CountingFit stop(8 + 7 * 3, 4, spline::OverBudget::Stop);
  CHECK(spline::run_hierarchical_fitting(stop, stop).stop_reason == spline::FitStopReason::Budget);
  CHECK(stop.fitted == std::vector<int>{0});
  CHECK(stop.tried == std::vector<int>{4});
  CountingFit halve(8 + 7 * 3, 4, spline::OverBudget::HalveMarking);
  const spline::HierarchicalFitResult r = spline::run_hierarchical_fitting(halve, halve);
  CHECK(r.stop_reason == spline::FitStopReason::Budget);
  // Level 1: 4 cells refused, 2 accepted (22 points); level 2: 4, 2 refused, 1 accepted (29).
  CHECK(halve.tried == std::vector<int>{4, 2, 4, 2, 1, 4, 2, 1});
  CHECK(halve.fitted == std::vector<int>{0, 1, 2});
  CHECK(r.levels == 2);
}

TEST_CASE("Algorithm 4 loop: an empty marking stops with its reason") {
  CountingFit f(1000, 0, spline::OverBudget::Stop);
  const spline::HierarchicalFitResult r = spline::run_hierarchical_fitting(f, f);
  CHECK(r.stop_reason == spline::FitStopReason::NoCells);
  CHECK(r.levels == 0);
  CHECK(f.tried.empty());
}

TEST_CASE("bulk marking: largest errors first until the fraction is covered, cut by the budget") {
  const std::vector<double> error = {1.0, 4.0, 2.0, 4.0, 0.5};
  bool over = true;
  CHECK(spline::bulk_mark({0, 1, 2, 3, 4}, error, 11.5, 0.5, 1e9, 0.0, &over) == std::vector<int>{1, 3});
  CHECK(!over);
  CHECK(spline::bulk_mark({0, 1, 2, 3, 4}, error, 11.5, 0.9, 1e9, 0.0, &over) == std::vector<int>{1, 3, 2, 0});
  CHECK(spline::bulk_mark({0, 1, 2, 3, 4}, error, 11.5, 0.9, 20.0, 7.0, &over) == std::vector<int>{1, 3});
  CHECK(spline::bulk_mark({0, 1, 2, 3, 4}, error, 11.5, 0.9, 5.0, 7.0, &over).empty());
  CHECK(over);
}
