// SPDX-License-Identifier: MIT
#include "core/common/version.h"

namespace volspline {

const char* version() { return "0.1.0"; }

}  // namespace volspline
