# SPDX-License-Identifier: MIT
set(TEST_SOURCES
  version_test.cpp
)
