// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace volspline::io {

/// GLB (binary glTF 2.0) container of a glTF JSON text and its binary buffer: the 12-byte header,
/// the JSON chunk padded with spaces and the BIN chunk (if `bin` is not empty) padded with zeros
/// to 4 bytes (glTF §4.4).
std::string glb_container(std::string json, std::string bin);

/// Appends `bytes` bytes from `data` to the binary buffer `bin` of a GLB and pads it with zeros to
/// a multiple of 4 bytes, so the next buffer view starts aligned for any component type; returns
/// the offset of the first appended byte (the buffer view's byteOffset).
std::size_t append_glb_bytes(std::string& bin, const void* data, std::size_t bytes);

/// The "min" (upper = false) or "max" (upper = true) of a VEC3 float accessor over the flat
/// positions xyz (x0 y0 z0 x1 ...): three floats, ±FLT_MAX where xyz is empty.
nlohmann::ordered_json glb_vec3_bound(const std::vector<float>& xyz, bool upper);

}  // namespace volspline::io
