// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

namespace volspline::cli {

/// The 8 corner vertex ids of a `--corners FILE` (whitespace-separated non-negative integers).
/// Throws volspline::Error naming the file and the first bad token or the wrong count.
std::vector<int> read_corner_ids(const std::string& path);

}  // namespace volspline::cli
