// SPDX-License-Identifier: MIT
#pragma once

#include <chrono>
#include <string>

#include "core/common/progress.h"

namespace volspline::cli {

/// A progress bar on stderr that appears only for work longer than one second.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled);
  ~ProgressBar();
  /// The callback to hand to a stage.
  Progress progress();
  /// Clears the bar line if one was drawn.
  void finish();

 private:
  bool update(const std::string& stage, double fraction);
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace volspline::cli
