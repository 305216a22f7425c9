// SPDX-License-Identifier: MIT
// Embind registration: JS names of the wasm entry points. The entry points only convert between
// JS values and core/pipeline structs; every one returns {ok:false, message} on failure, so no
// C++ exception or abort reaches JS.
#include <emscripten/bind.h>

#include <string>

#include "core/common/version.h"
#include "wasm/gpc_binding.h"
#include "wasm/lens_binding.h"
#include "wasm/mesh2spline_binding.h"
#include "wasm/mesh_info_binding.h"
#include "wasm/spline_quality_binding.h"
#include "wasm/vol2spline_binding.h"
#include "wasm/volume_binding.h"

namespace {

std::string version() { return volspline::version(); }

}  // namespace

EMSCRIPTEN_BINDINGS(volspline) {
  emscripten::function("version", &version);
  emscripten::function("meshInfo", &volspline::wasm::mesh_info);
  emscripten::function("decodeImage", &volspline::wasm::decode_image);
  emscripten::function("encodePng", &volspline::wasm::encode_png);
  emscripten::function("lens", &volspline::wasm::lens);
  emscripten::function("mesh2spline", &volspline::wasm::mesh2spline);
  emscripten::function("gpc", &volspline::wasm::gpc);
  emscripten::function("splineCut", &volspline::wasm::spline_cut);
  emscripten::function("splineQuality", &volspline::wasm::spline_quality);
  emscripten::function("loadVolume", &volspline::wasm::load_volume);
  emscripten::function("vol2spline", &volspline::wasm::vol2spline);
  emscripten::class_<volspline::wasm::LensSessionBinding>("LensSession")
      .constructor<>()
      .function("run", &volspline::wasm::LensSessionBinding::run)
      .function("counters", &volspline::wasm::LensSessionBinding::counters)
      .function("clear", &volspline::wasm::LensSessionBinding::clear);
}
