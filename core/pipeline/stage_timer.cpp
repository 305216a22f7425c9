// SPDX-License-Identifier: MIT
#include "core/pipeline/stage_timer.h"

namespace volspline::pipeline {

StageTimer::StageTimer(std::vector<std::pair<std::string, double>>& times)
    : times_(times), last_(std::chrono::steady_clock::now()) {}

void StageTimer::end_stage(const std::string& stage) {
  const auto now = std::chrono::steady_clock::now();
  times_.emplace_back(stage, std::chrono::duration<double>(now - last_).count());
  last_ = now;
}

}  // namespace volspline::pipeline
