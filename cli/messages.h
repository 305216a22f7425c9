// SPDX-License-Identifier: MIT
#pragma once

#include <string>

namespace volspline::cli {

/// A core message as the command line shows it: each option field the core names in backticks
/// (`max_rms_rel`) becomes the flag that sets it (--max-rms); a field without a flag keeps its
/// name, without the backticks.
std::string with_flag_names(const std::string& message);

/// The message with every control byte (C0, DEL, and the C1 range as UTF-8 or raw bytes) written
/// as \xNN, so bytes echoed from a file cannot drive the terminal.
std::string printable(const std::string& message);

}  // namespace volspline::cli
