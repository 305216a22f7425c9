// SPDX-License-Identifier: MIT
#pragma once

#include <stdexcept>
#include <string>

namespace volspline {

/// Bad user data (file, option, mesh): the message names the file or element and the problem.
/// Broken caller preconditions are bugs and use assert instead.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Thrown by a stage when the progress callback asked it to stop.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace volspline
