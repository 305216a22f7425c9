// SPDX-License-Identifier: MIT
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "core/common/progress.h"

namespace volspline::cli {

/// Progress on stderr for work longer than one second. On a terminal, a bar redrawn in place
/// (with the seconds spent, so a long stage without reports still shows it is alive); otherwise
/// (a log file, a pipe) plain lines "stage  NN %  (T s)", one per stage and at most one per
/// 10 s within a stage, never carriage returns.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  /// The callback to hand to a stage.
  Progress progress();
  /// Stops the display and clears the bar line if one was drawn.
  void finish();

 private:
  bool update(const std::string& stage, double fraction);
  void tick();  // the display thread
  void draw_locked(std::chrono::steady_clock::time_point now);

  bool enabled_;
  bool terminal_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  bool drawn_ = false;
  std::string stage_, printed_stage_;
  double fraction_ = 0.0;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_line_;
  std::thread thread_;
};

}  // namespace volspline::cli
