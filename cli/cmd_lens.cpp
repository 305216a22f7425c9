// SPDX-License-Identifier: MIT
#include "cli/args.h"
#include "cli/commands.h"

namespace volspline::cli {

int run_lens(const std::vector<std::string>& argv) {
  throw UsageError("lens: not implemented yet");
}

}  // namespace volspline::cli
