// SPDX-License-Identifier: MIT
#include "wasm/lens_binding.h"

#include <cstdint>
#include <vector>

#include "core/common/error.h"
#include "core/io/image_io.h"
#include "core/pipeline/lens_job.h"
#include "core/pipeline/lens_session.h"
#include "wasm/guarded.h"
#include "wasm/js_values.h"

namespace volspline::wasm {

using emscripten::val;

namespace {

val image_to_js(const Image& image) {
  val out = val::object();
  out.set("width", image.width);
  out.set("height", image.height);
  out.set("channels", image.channels);
  out.set("pixels", uint8_array(image.pixels.data(), image.pixels.size()));
  return out;
}

Image image_from_js(const val& image, const std::string& what) {
  if (image.isUndefined() || image.isNull() || image.typeOf().as<std::string>() != "object")
    throw Error(what + ": expected {width, height, channels, pixels}");
  Image out;
  const auto dimension = [&](const char* key) {
    const double x = number_option(image, key, -1);
    if (!(x >= 0 && x <= 1 << 20) || x != static_cast<int>(x))
      throw Error(what + ": '" + key + "' must be a non-negative integer");
    return static_cast<int>(x);
  };
  out.width = dimension("width");
  out.height = dimension("height");
  out.channels = dimension("channels");
  const std::string bytes = bytes_from_js(image["pixels"], what + " pixels");
  if (bytes.size() != std::size_t(out.width) * out.height * out.channels)
    throw Error(what + ": pixels has " + std::to_string(bytes.size()) + " bytes, expected width*height*channels = " +
                std::to_string(std::size_t(out.width) * out.height * out.channels));
  out.pixels.assign(bytes.begin(), bytes.end());
  return out;
}

lens::Roi roi_from_js(const val& item, int index) {
  const std::string where = "roi " + std::to_string(index);
  if (item.isString()) {
    lens::RoiSpec spec = lens::parse_roi_spec(item.as<std::string>());
    if (!spec.mask_path.empty()) throw Error(where + ": mask files are not available in the browser");
    return spec.roi;
  }
  if (item.isUndefined() || item.isNull() || item.typeOf().as<std::string>() != "object")
    throw Error(where + ": expected {shape, values} or a text like \"circle:CX,CY,R\"");
  lens::Roi roi;
  const std::string shape = string_option(item, "shape", "circle");
  if (shape == "circle") roi.shape = lens::RoiShape::Circle;
  else if (shape == "rect") roi.shape = lens::RoiShape::Rect;
  else if (shape == "polygon") roi.shape = lens::RoiShape::Polygon;
  else throw Error(where + ": unknown shape '" + shape + "' (circle, rect, polygon)");
  const val values = item["values"];
  if (!values.isArray()) throw Error(where + ": 'values' must be an array of numbers");
  const int n = values["length"].as<int>();
  for (int i = 0; i < n; ++i) {
    const val v = values[i];
    if (!v.isNumber()) throw Error(where + ": values[" + std::to_string(i) + "] is not a number");
    roi.values.push_back(v.as<double>());
  }
  const std::size_t expected = roi.shape == lens::RoiShape::Circle ? 3 : roi.shape == lens::RoiShape::Rect ? 4 : 0;
  if (expected != 0 && roi.values.size() != expected)
    throw Error(where + ": a " + shape + " needs " + std::to_string(expected) + " values, got " +
                std::to_string(roi.values.size()));
  if (roi.shape == lens::RoiShape::Polygon && (roi.values.size() < 6 || roi.values.size() % 2 != 0))
    throw Error(where + ": a polygon needs at least 3 x,y pairs");
  roi.name = where + " (" + shape + ")";
  return roi;
}

pipeline::LensOptions lens_options_from_js(const val& o) {
  pipeline::LensOptions options;
  const std::string method = string_option(o, "method", "metric");
  if (method == "metric") options.method = pipeline::LensMethod::Metric;
  else if (method == "fisheye") options.method = pipeline::LensMethod::Fisheye;
  else if (method == "bifocal") options.method = pipeline::LensMethod::Bifocal;
  else if (method == "zoom") options.method = pipeline::LensMethod::Zoom;
  else throw Error("option 'method': unknown '" + method + "' (metric, fisheye, bifocal, zoom)");
  const std::string boundary = string_option(o, "boundary", "pinned");
  if (boundary == "pinned") options.boundary = pipeline::LensBoundary::Pinned;
  else if (boundary == "square") options.boundary = pipeline::LensBoundary::Square;
  else throw Error("option 'boundary': unknown '" + boundary + "' (pinned, square)");
  options.magnification = number_option(o, "magnification", options.magnification);
  options.height = number_option(o, "height", options.height);
  if (!o.isUndefined() && !o.isNull() && !o["height_scale"].isUndefined()) {
    const val scales = o["height_scale"];
    if (!scales.isArray()) throw Error("option 'height_scale': expected an array of numbers, one per ROI");
    const int n = scales["length"].as<int>();
    for (int i = 0; i < n; ++i) {
      if (!scales[i].isNumber()) throw Error("option 'height_scale': entry " + std::to_string(i) + " is not a number");
      options.height_scale.push_back(scales[i].as<double>());
    }
  }
  options.alpha = number_option(o, "alpha", options.alpha);
  const auto integer = [&](const char* key, int fallback) {
    const double x = number_option(o, key, fallback);
    if (x != static_cast<double>(static_cast<long long>(x)) || x < -1e9 || x > 1e9)
      throw Error(std::string("option '") + key + "': expected an integer");
    return static_cast<int>(x);
  };
  options.grid = integer("grid", options.grid);
  options.band = number_option(o, "band", options.band);
  options.tol_rel = number_option(o, "tol_rel", options.tol_rel);
  options.max_iterations = integer("max_iterations", options.max_iterations);
  options.render = bool_option(o, "render", true) ? pipeline::LensOptions::Render::On : pipeline::LensOptions::Render::Off;
  const std::string mode = string_option(o, "mode", "full");
  if (mode == "full") options.mode = pipeline::LensMode::Full;
  else if (mode == "live") options.mode = pipeline::LensMode::Live;
  else throw Error("option 'mode': unknown '" + mode + "' (full, live)");
  return options;  // ranges are checked by run_lens
}

val stats_to_js(const pipeline::LensStats& s) {
  val out = val::object();
  out.set("distortion_sum", s.distortion_sum);
  out.set("distortion_max", s.distortion_max);
  out.set("distortion_sum_focus", s.distortion_sum_focus);
  out.set("distortion_max_focus", s.distortion_max_focus);
  out.set("magnification_center", s.magnification_center);
  val per_roi = val::array();
  for (double m : s.magnification_per_roi) per_roi.call<void>("push", m);
  out.set("magnification_per_roi", per_roi);
  val scales = val::array();
  for (double x : s.height_scale_per_roi) scales.call<void>("push", x);
  out.set("height_scale_per_roi", scales);
  out.set("flipped_triangles", s.flipped_triangles);
  out.set("magnification_requested", s.magnification_requested);
  out.set("magnification_limited", s.magnification_limited);
  out.set("iterations", s.iterations);
  out.set("converged", s.converged);
  out.set("translated", s.translated);
  out.set("height", s.height);
  out.set("baseline_parameter", s.baseline_parameter);
  out.set("vertices", s.vertices);
  out.set("triangles", s.triangles);
  out.set("ms_total", s.ms_total);
  out.set("ms_calibration", s.ms_calibration);
  out.set("ms_mesh", s.ms_mesh);
  out.set("ms_factorize", s.ms_factorize);
  out.set("ms_per_iteration", s.ms_per_iteration);
  out.set("ms_render", s.ms_render);
  return out;
}

val points2_to_js(const Eigen::MatrixX2d& points) {
  std::vector<float> flat(static_cast<std::size_t>(points.rows()) * 2);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    flat[2 * i] = static_cast<float>(points(i, 0));
    flat[2 * i + 1] = static_cast<float>(points(i, 1));
  }
  return float32_array(flat.data(), flat.size());
}

}  // namespace

val decode_image(const val& bytes, const std::string& name) {
  return guarded([&] {
    const Image image = io::decode_image(bytes_from_js(bytes, "image '" + name + "'"), name);
    val out = val::object();
    out.set("ok", true);
    out.set("image", image_to_js(image));
    return out;
  });
}

val encode_png(const val& image) {
  return guarded([&] {
    const std::string png = io::encode_png(image_from_js(image, "image"));
    val out = val::object();
    out.set("ok", true);
    out.set("bytes", uint8_array(reinterpret_cast<const std::uint8_t*>(png.data()), png.size()));
    return out;
  });
}

namespace {

// Parses the JS arguments, runs `job(input, options, progress)` and converts its LensResult.
template <class Job>
val run_lens_js(const val& image, const val& rois, const val& options, const val& progress, Job&& job) {
  pipeline::LensInput input;
  input.name = "image";
  if (!image.isUndefined() && !image.isNull() && image.typeOf().as<std::string>() == "object")
    input.name = string_option(image, "name", "image");
  input.image = image_from_js(image, "image '" + input.name + "'");
  if (!rois.isArray()) throw Error("lens: rois must be an array");
  const int n = rois["length"].as<int>();
  for (int i = 0; i < n; ++i) input.rois.push_back(roi_from_js(rois[i], i));
  const pipeline::LensResult result = job(input, lens_options_from_js(options), progress_from_js(progress));

  val out = val::object();
  out.set("ok", true);
  out.set("stats", stats_to_js(result.stats));
  out.set("positions", points2_to_js(result.positions));
  out.set("texture", points2_to_js(result.texture));
  const std::vector<std::uint32_t> triangles(result.triangles.data(), result.triangles.data() + result.triangles.size());
  out.set("triangles", uint32_array(triangles.data(), triangles.size()));
  out.set("image", result.image.pixels.empty() ? val::null() : image_to_js(result.image));
  return out;
}

val counters_to_js(const pipeline::LensSessionCounters& c) {
  val out = val::object();
  out.set("runs", c.runs);
  out.set("mesh_builds", c.mesh_builds);
  out.set("mesh_reuses", c.mesh_reuses);
  out.set("calibrations", c.calibrations);
  out.set("calibration_reuses", c.calibration_reuses);
  out.set("translation_reuses", c.translation_reuses);
  return out;
}

}  // namespace

val lens(const val& image, const val& rois, const val& options, const val& progress) {
  return guarded([&] {
    return run_lens_js(image, rois, options, progress,
                       [](const pipeline::LensInput& in, const pipeline::LensOptions& o, const Progress& p) {
                         return pipeline::run_lens(in, o, p);
                       });
  });
}

LensSessionBinding::LensSessionBinding() : session_(std::make_unique<pipeline::LensSession>()) {}
LensSessionBinding::~LensSessionBinding() = default;

val LensSessionBinding::run(const val& image, const val& rois, const val& options, const val& progress) {
  return guarded([&] {
    val out = run_lens_js(image, rois, options, progress,
                          [this](const pipeline::LensInput& in, const pipeline::LensOptions& o, const Progress& p) {
                            return session_->run(in, o, p);
                          });
    out.set("session", counters_to_js(session_->counters()));
    return out;
  });
}

val LensSessionBinding::counters() const { return counters_to_js(session_->counters()); }

void LensSessionBinding::clear() { session_->clear(); }

}  // namespace volspline::wasm
