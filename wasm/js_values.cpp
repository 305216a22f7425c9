// SPDX-License-Identifier: MIT
#include "wasm/js_values.h"

#include <cmath>

#include "core/common/error.h"

namespace volspline::wasm {

using emscripten::val;

namespace {

template <class T>
val typed_array_copy(const char* constructor, const T* data, std::size_t n) {
  // The view aliases the wasm heap; constructing a typed array from it copies, so the result
  // stays valid after the C++ data is freed or the heap grows.
  return val::global(constructor).new_(emscripten::typed_memory_view(n, data));
}

bool is_plain_missing(const val& v) { return v.isUndefined() || v.isNull(); }

val option_value(const val& options, const char* key) {
  if (is_plain_missing(options)) return val::undefined();
  if (options.typeOf().as<std::string>() != "object")
    throw Error("options: expected an object, got " + options.typeOf().as<std::string>());
  return options[key];
}

}  // namespace

std::string bytes_from_js(const val& bytes, const std::string& what) {
  val array = bytes;
  if (!is_plain_missing(bytes) && bytes.instanceof(val::global("ArrayBuffer")))
    array = val::global("Uint8Array").new_(bytes);
  if (is_plain_missing(array) || !array.instanceof(val::global("Uint8Array")))
    throw Error(what + ": expected a Uint8Array or ArrayBuffer");
  const std::size_t n = array["length"].as<std::size_t>();
  std::string out(n, '\0');
  if (n > 0) {
    // No allocation happens between making the view and filling it, so the heap cannot move.
    val view(emscripten::typed_memory_view(n, reinterpret_cast<unsigned char*>(out.data())));
    view.call<void>("set", array);
  }
  return out;
}

val float32_array(const float* data, std::size_t n) { return typed_array_copy("Float32Array", data, n); }
val float64_array(const double* data, std::size_t n) { return typed_array_copy("Float64Array", data, n); }
val uint32_array(const std::uint32_t* data, std::size_t n) { return typed_array_copy("Uint32Array", data, n); }
val uint8_array(const std::uint8_t* data, std::size_t n) { return typed_array_copy("Uint8Array", data, n); }

double number_option(const val& options, const char* key, double fallback) {
  const val v = option_value(options, key);
  if (v.isUndefined()) return fallback;
  if (!v.isNumber()) throw Error(std::string("option '") + key + "': expected a number");
  const double x = v.as<double>();
  if (!std::isfinite(x)) throw Error(std::string("option '") + key + "': expected a finite number");
  return x;
}

int integer_option(const val& o, const char* key, int fallback, int lo, int hi) {
  const double x = number_option(o, key, fallback);
  if (x != static_cast<double>(static_cast<long long>(x)) || x < lo || x > hi)
    throw Error(std::string("option '") + key + "': expected an integer in [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "]");
  return static_cast<int>(x);
}

std::vector<int> corner_ids_option(const val& o) {
  std::vector<int> ids;
  if (!o.isUndefined() && !o.isNull()) {
    const val corners = o["corners"];
    if (!corners.isUndefined() && !corners.isNull()) {
      if (!corners.isArray()) throw Error("option 'corners': expected an array of 8 vertex ids");
      const int n = corners["length"].as<int>();
      for (int i = 0; i < n; ++i) {
        const val c = corners[i];
        if (!c.isNumber() || c.as<double>() != static_cast<double>(static_cast<int>(c.as<double>())) || c.as<double>() < 0)
          throw Error("option 'corners': entry " + std::to_string(i) + " is not a vertex id");
        ids.push_back(c.as<int>());
      }
    }
  }
  return ids;
}

std::string string_option(const val& options, const char* key, const std::string& fallback) {
  const val v = option_value(options, key);
  if (v.isUndefined()) return fallback;
  if (!v.isString()) throw Error(std::string("option '") + key + "': expected a string");
  return v.as<std::string>();
}

bool bool_option(const val& options, const char* key, bool fallback) {
  const val v = option_value(options, key);
  if (v.isUndefined()) return fallback;
  if (v.typeOf().as<std::string>() != "boolean")
    throw Error(std::string("option '") + key + "': expected true or false");
  return v.as<bool>();
}

Progress progress_from_js(const val& callback) {
  if (is_plain_missing(callback)) return Progress();
  if (callback.typeOf().as<std::string>() != "function")
    throw Error("progress: expected a function (stage, fraction) -> boolean");
  return Progress([callback](const std::string& stage, double fraction) {
    return !callback(stage, fraction).isFalse();
  });
}

emscripten::val stage_times_object(const std::vector<std::pair<std::string, double>>& times_s) {
  emscripten::val times = emscripten::val::object();
  double total = 0;
  for (const auto& [stage, seconds] : times_s) {
    times.set(stage, seconds);
    total += seconds;
  }
  times.set("total", total);
  return times;
}

}  // namespace volspline::wasm
