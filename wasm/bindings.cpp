// SPDX-License-Identifier: MIT
// Embind layer: converts between JS values and core/pipeline structs, nothing else. Every entry
// point catches, so no C++ exception or abort reaches JS: failures return {ok:false, message}.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <exception>
#include <new>
#include <string>

#include "core/common/error.h"
#include "core/common/version.h"

namespace {

using emscripten::val;

val failure(const std::string& message) {
  val out = val::object();
  out.set("ok", false);
  out.set("message", message);
  return out;
}

/// Runs f() -> val and converts every exception into {ok:false, message}.
template <class F>
val guarded(F&& f) {
  try {
    return f();
  } catch (const volspline::Error& e) {
    return failure(e.what());
  } catch (const volspline::Cancelled&) {
    return failure("cancelled");
  } catch (const std::bad_alloc&) {
    return failure("out of memory");
  } catch (const std::exception& e) {
    return failure(std::string("internal error: ") + e.what());
  }
}

std::string version() { return volspline::version(); }

}  // namespace

EMSCRIPTEN_BINDINGS(volspline) {
  emscripten::function("version", &version);
}
