// SPDX-License-Identifier: MIT
#pragma once
// The error boundary of every wasm entry point: no C++ exception or abort reaches JS.
#include <emscripten/val.h>

#include <exception>
#include <new>
#include <string>

#include "core/common/error.h"

namespace volspline::wasm {

/// {ok:false, message} as returned to JS on failure.
inline emscripten::val failure(const std::string& message) {
  emscripten::val out = emscripten::val::object();
  out.set("ok", false);
  out.set("message", message);
  return out;
}

/// Runs f() -> val and converts every exception into {ok:false, message}; the message of a
/// volspline::Error is passed through unchanged, a cancellation gives "cancelled".
template <class F>
emscripten::val guarded(F&& f) {
  try {
    return f();
  } catch (const volspline::Error& e) {
    return failure(e.what());
  } catch (const volspline::Cancelled&) {
    return failure("cancelled");
  } catch (const std::bad_alloc&) {
    return failure("out of memory: the input is too large for the browser's 2 GB WebAssembly memory");
  } catch (const std::exception& e) {
    return failure(std::string("internal error: ") + e.what());
  }
}

}  // namespace volspline::wasm
