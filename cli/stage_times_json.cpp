// SPDX-License-Identifier: MIT
#include "cli/stage_times_json.h"

namespace volspline::cli {

nlohmann::ordered_json stage_times_json(const std::vector<std::pair<std::string, double>>& times_s) {
  nlohmann::ordered_json times;
  double total = 0.0;
  for (const auto& [stage, seconds] : times_s) {
    times[stage] = seconds;
    total += seconds;
  }
  times["total"] = total;
  return times;
}

}  // namespace volspline::cli
