// SPDX-License-Identifier: MIT
#pragma once

#include <functional>
#include <string>

#include "core/common/error.h"

namespace volspline {

/// The one progress and cancellation channel of every stage.
/// The callback gets the stage name and the fraction done in [0, 1]; returning false asks the
/// stage to stop, which it does by throwing volspline::Cancelled at its next report.
class Progress {
 public:
  using Callback = std::function<bool(const std::string& stage, double fraction)>;

  Progress() = default;
  explicit Progress(Callback callback) : callback_(std::move(callback)) {}

  /// Reports progress; throws Cancelled if the callback returned false.
  void report(const std::string& stage, double fraction) const {
    if (callback_ && !callback_(stage, fraction)) throw Cancelled();
  }

 private:
  Callback callback_;
};

}  // namespace volspline
