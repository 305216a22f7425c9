// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

namespace volspline::cli {

/// Each command gets its arguments without the program and command names and returns the exit
/// code (0 ok, 1 failed job). Usage errors throw UsageError, bad input throws volspline::Error;
/// main maps both to exit code 2.
int run_info(const std::vector<std::string>& argv);
int run_gpc(const std::vector<std::string>& argv);
int run_lens(const std::vector<std::string>& argv);
int run_mesh2spline(const std::vector<std::string>& argv);
int run_eval(const std::vector<std::string>& argv);
int run_vol2spline(const std::vector<std::string>& argv);

}  // namespace volspline::cli
