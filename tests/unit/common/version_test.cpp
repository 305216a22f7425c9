// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "core/common/version.h"

TEST_CASE("version is MAJOR.MINOR.PATCH") {
  const std::string v = volspline::version();
  CHECK(std::count(v.begin(), v.end(), '.') == 2);
}
