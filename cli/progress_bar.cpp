// SPDX-License-Identifier: MIT
#include "cli/progress_bar.h"

#include <cstdio>

namespace volspline::cli {

ProgressBar::ProgressBar(bool enabled)
    : enabled_(enabled), start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

ProgressBar::~ProgressBar() { finish(); }

Progress ProgressBar::progress() {
  return Progress([this](const std::string& stage, double fraction) { return update(stage, fraction); });
}

bool ProgressBar::update(const std::string& stage, double fraction) {
  if (!enabled_) return true;
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < std::chrono::seconds(1)) return true;
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(100)) return true;
  last_draw_ = now;
  drawn_ = true;
  if (fraction < 0) fraction = 0;
  if (fraction > 1) fraction = 1;
  const int width = 30;
  const int filled = static_cast<int>(fraction * width + 0.5);
  std::string bar(static_cast<size_t>(filled), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "\r%-24.24s [%s] %3d%%", stage.c_str(), bar.c_str(), static_cast<int>(fraction * 100 + 0.5));
  std::fflush(stderr);
  return true;
}

void ProgressBar::finish() {
  if (drawn_) {
    std::fprintf(stderr, "\r%*s\r", 64, "");
    std::fflush(stderr);
    drawn_ = false;
  }
}

}  // namespace volspline::cli
