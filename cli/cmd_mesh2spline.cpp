// SPDX-License-Identifier: MIT
#include "cli/args.h"
#include "cli/commands.h"

namespace volspline::cli {

int run_mesh2spline(const std::vector<std::string>& argv) {
  throw UsageError("mesh2spline: not implemented yet");
}

}  // namespace volspline::cli
