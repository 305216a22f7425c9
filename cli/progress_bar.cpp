// SPDX-License-Identifier: MIT
#include "cli/progress_bar.h"

#include <unistd.h>

#include <cstdio>

namespace volspline::cli {

ProgressBar::ProgressBar(bool enabled)
    : enabled_(enabled), terminal_(::isatty(STDERR_FILENO) == 1), start_(std::chrono::steady_clock::now()) {
  if (enabled_) thread_ = std::thread([this] { tick(); });
}

ProgressBar::~ProgressBar() { finish(); }

Progress ProgressBar::progress() {
  return Progress([this](const std::string& stage, double fraction) { return update(stage, fraction); });
}

bool ProgressBar::update(const std::string& stage, double fraction) {
  if (!enabled_) return true;
  std::lock_guard<std::mutex> lock(mutex_);
  stage_ = stage;
  fraction_ = fraction < 0 ? 0 : fraction > 1 ? 1 : fraction;
  return true;
}

void ProgressBar::tick() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    wake_.wait_for(lock, std::chrono::milliseconds(200));
    if (stop_) break;
    const auto now = std::chrono::steady_clock::now();
    if (now - start_ >= std::chrono::seconds(1) && !stage_.empty()) draw_locked(now);
  }
}

void ProgressBar::draw_locked(std::chrono::steady_clock::time_point now) {
  const int percent = static_cast<int>(fraction_ * 100 + 0.5);
  const double seconds = std::chrono::duration<double>(now - start_).count();
  if (terminal_) {
    const int width = 30;
    std::string bar(static_cast<size_t>(fraction_ * width + 0.5), '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r%-24.24s [%s] %3d%% %5.0fs", stage_.c_str(), bar.c_str(), percent, seconds);
    drawn_ = true;
  } else {
    if (stage_ == printed_stage_ && now - last_line_ < std::chrono::seconds(10)) return;
    std::fprintf(stderr, "%s  %d %%  (%.0f s)\n", stage_.c_str(), percent, seconds);
    printed_stage_ = stage_;
    last_line_ = now;
  }
  std::fflush(stderr);
}

void ProgressBar::finish() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return;
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (drawn_) {
    std::fprintf(stderr, "\r%*s\r", 72, "");
    std::fflush(stderr);
    drawn_ = false;
  }
}

}  // namespace volspline::cli
