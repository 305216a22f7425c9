// SPDX-License-Identifier: MIT
#pragma once

namespace volspline {

/// The library version, "MAJOR.MINOR.PATCH".
const char* version();

}  // namespace volspline
