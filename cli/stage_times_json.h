// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace volspline::cli {

/// The "times_s" object of a job's stats JSON: one key per stage with its wall time in seconds,
/// in run order, then "total", their sum in that order.
nlohmann::ordered_json stage_times_json(const std::vector<std::pair<std::string, double>>& times_s);

}  // namespace volspline::cli
