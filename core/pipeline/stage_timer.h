// SPDX-License-Identifier: MIT
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace volspline::pipeline {

/// Wall time per stage of a job, for the stats' times_s: each end_stage(name) appends the seconds
/// since the previous one (or since construction), in run order. Measures only; no result depends
/// on it.
class StageTimer {
 public:
  /// times: the list the stages are appended to; must outlive the timer.
  explicit StageTimer(std::vector<std::pair<std::string, double>>& times);
  /// Appends (stage, seconds since the last call or construction).
  void end_stage(const std::string& stage);

 private:
  std::vector<std::pair<std::string, double>>& times_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace volspline::pipeline
