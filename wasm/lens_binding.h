// SPDX-License-Identifier: MIT
#pragma once

#include <emscripten/val.h>

#include <memory>
#include <string>

namespace volspline::wasm {

/// JS: decodeImage(bytes: Uint8Array|ArrayBuffer, name: string) ->
///   {ok:true, image: {width, height, channels, pixels: Uint8Array}} or {ok:false, message}
/// (PNG or JPEG; the message names `name`).
emscripten::val decode_image(const emscripten::val& bytes, const std::string& name);

/// JS: encodePng(image: {width, height, channels, pixels}) -> {ok:true, bytes: Uint8Array} or
/// {ok:false, message}.
emscripten::val encode_png(const emscripten::val& image);

/// JS: lens(image, rois, options, progress) -> {ok:true, stats, positions, texture, triangles, image}
/// or {ok:false, message}.
///   image   {width, height, channels (1–4), pixels: Uint8Array, name?}, row-major, interleaved;
///   rois    array of {shape: 'circle'|'rect'|'polygon', values: [...] (pixels)} or of texts
///           "circle:CX,CY,R" / "rect:X,Y,W,H" / "polygon:X1,Y1,..." (see core/lens/roi.h);
///   options plain object, every key optional (defaults of pipeline::LensOptions): method
///           ('metric'|'fisheye'|'bifocal'|'zoom'), magnification, height, alpha, grid,
///           boundary ('pinned'|'square'), band, tol_rel, max_iterations, render (boolean),
///           mode ('full'|'live': pipeline::LensMode; only a LensSession translates live requests);
///   progress function (stage, fraction) -> boolean or undefined/null (all four arguments are
///           required by Embind), false cancels ("cancelled");
/// Output: stats with the keys of pipeline::LensStats; positions and texture Float32Array (2 per
/// vertex, output and input pixel coordinates); triangles Uint32Array (3 per triangle); image as
/// the input image object, or null when options.render is false.
emscripten::val lens(const emscripten::val& image, const emscripten::val& rois, const emscripten::val& options,
                     const emscripten::val& progress);

}  // namespace volspline::wasm

namespace volspline::pipeline {
class LensSession;
}

namespace volspline::wasm {

/// JS class LensSession (pipeline::LensSession), for live interaction:
///   const s = new LensSession();
///   s.run(image, rois, options, progress) -> exactly what lens(...) returns for the same arguments,
///       plus `session` (the counters below); the lens mesh, texture, factorization and calibrated
///       h0 of earlier runs are reused, so a new α at a given height only re-runs the iterations;
///   s.counters() -> {runs, mesh_builds, mesh_reuses, calibrations, calibration_reuses, translation_reuses};
///   s.clear() drops the caches; s.delete() frees the session (Embind objects are not collected).
class LensSessionBinding {
 public:
  /// A session with empty caches (JS: new LensSession()).
  LensSessionBinding();
  ~LensSessionBinding();
  /// See the class comment; never throws ({ok:false, message} on failure).
  emscripten::val run(const emscripten::val& image, const emscripten::val& rois, const emscripten::val& options,
                      const emscripten::val& progress);
  /// {runs, mesh_builds, mesh_reuses, calibrations, calibration_reuses, translation_reuses}.
  emscripten::val counters() const;
  /// Drops every cached mesh, factorization and calibration.
  void clear();

 private:
  std::unique_ptr<pipeline::LensSession> session_;
};

}  // namespace volspline::wasm
