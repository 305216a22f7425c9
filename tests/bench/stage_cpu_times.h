// SPDX-License-Identifier: MIT
#pragma once

#include <algorithm>
#include <ctime>
#include <map>
#include <string>
#include <vector>

#include "core/common/progress.h"

namespace volspline::bench {

/// The median of v (the upper middle value of an even count); 0 if v is empty.
inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// CPU seconds per stage of a job, from its progress reports, over several runs. A stage runs
/// from its first report to the first report of the next stage (further reports of the same
/// stage continue it); the last stage of a run has no end and is not recorded.
class StageCpuTimes {
 public:
  /// The callback for one run: pass it to the job. It records into this object, which must
  /// outlive the run; each call starts a new run.
  Progress run_progress() {
    stage_.clear();
    return Progress([this](const std::string& next, double) {
      if (next == stage_) return true;
      const std::clock_t now = std::clock();
      if (!stage_.empty()) {
        if (!seconds_.count(stage_)) order_.push_back(stage_);
        seconds_[stage_].push_back(double(now - stage_start_) / CLOCKS_PER_SEC);
      }
      stage_ = next;
      stage_start_ = now;
      return true;
    });
  }

  /// The recorded stages in the order they first ended.
  const std::vector<std::string>& stages() const { return order_; }
  /// The median over the runs of one recorded stage's CPU seconds.
  double median_seconds(const std::string& stage) const { return median(seconds_.at(stage)); }

 private:
  std::map<std::string, std::vector<double>> seconds_;
  std::vector<std::string> order_;
  std::string stage_;
  std::clock_t stage_start_ = 0;
};

}  // namespace volspline::bench
