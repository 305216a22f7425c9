// SPDX-License-Identifier: MIT
#include "cli/args.h"
#include "cli/commands.h"

namespace volspline::cli {

int run_eval(const std::vector<std::string>& argv) {
  throw UsageError("eval: not implemented yet");
}

}  // namespace volspline::cli
