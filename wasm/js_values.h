// SPDX-License-Identifier: MIT
#pragma once
// Conversions between JS values and the plain C++ data of core/pipeline: typed arrays in and out,
// plain option objects, the progress callback. Only the wasm adapters include this.
#include <emscripten/val.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/common/progress.h"

namespace volspline::wasm {

/// Copies a Uint8Array or ArrayBuffer into a byte string.
/// Throws volspline::Error naming `what` if `bytes` is neither.
std::string bytes_from_js(const emscripten::val& bytes, const std::string& what);

/// New JS Float32Array holding a copy of data[0..n).
emscripten::val float32_array(const float* data, std::size_t n);
/// New JS Float64Array holding a copy of data[0..n).
emscripten::val float64_array(const double* data, std::size_t n);
/// New JS Uint32Array holding a copy of data[0..n).
emscripten::val uint32_array(const std::uint32_t* data, std::size_t n);
/// New JS Uint8Array holding a copy of data[0..n).
emscripten::val uint8_array(const std::uint8_t* data, std::size_t n);

/// Reads options.key as a finite number, `fallback` if the key is missing or undefined.
/// `options` may be undefined or null (all defaults). Throws volspline::Error naming the key if
/// the value is present but not a finite number, or if `options` is not an object.
double number_option(const emscripten::val& options, const char* key, double fallback);
/// Reads options.key as an integer in [lo, hi], `fallback` if missing. Throws volspline::Error
/// naming the key and the range otherwise.
int integer_option(const emscripten::val& options, const char* key, int fallback, int lo, int hi);
/// Reads options.corners as vertex ids (empty if missing). Throws volspline::Error naming the entry
/// that is not a non-negative integer, or if it is not an array.
std::vector<int> corner_ids_option(const emscripten::val& options);
/// Reads options.key as a string, `fallback` if missing. Throws volspline::Error naming the key
/// if the value is present but not a string.
std::string string_option(const emscripten::val& options, const char* key, const std::string& fallback);
/// Reads options.key as a boolean, `fallback` if missing. Throws volspline::Error naming the key
/// if the value is present but not a boolean.
bool bool_option(const emscripten::val& options, const char* key, bool fallback);

/// Wraps a JS function (stage: string, fraction: number) -> boolean|undefined as the stage
/// progress channel; an explicit `false` asks the stage to stop. Undefined or null gives no
/// reporting. Throws volspline::Error if `callback` is something else.
Progress progress_from_js(const emscripten::val& callback);

/// New JS object {stage: seconds, ..., total: Σ seconds} from a job's per-stage times (run order).
emscripten::val stage_times_object(const std::vector<std::pair<std::string, double>>& times_s);

}  // namespace volspline::wasm
