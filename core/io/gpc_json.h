// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/polycube/gpc_domain.h"

namespace volspline::io {

/// A GPC domain as UTF-8 JSON (schema in the README, "format": "volspline-gpc"), numbers at
/// shortest round-trip precision, so write → read → write is byte-identical.
std::string serialize_gpc_domain(const polycube::GpcDomain& domain);
/// Parses serialize_gpc_domain's output. Throws volspline::Error naming `source` and the first
/// problem (not JSON, wrong format or version, missing or mistyped field, ids out of range).
polycube::GpcDomain parse_gpc_domain(const std::string& text, const std::string& source);
/// Writes serialize_gpc_domain atomically. Throws volspline::Error naming the path on failure.
void write_gpc_domain(const std::string& path, const polycube::GpcDomain& domain);
/// Reads and parses a file written by write_gpc_domain.
polycube::GpcDomain read_gpc_domain(const std::string& path);

}  // namespace volspline::io
