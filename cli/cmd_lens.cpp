// SPDX-License-Identifier: MIT
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/output_files.h"
#include "cli/progress_bar.h"
#include "core/common/error.h"
#include "core/io/file_bytes.h"
#include "core/io/image_io.h"
#include "core/io/mesh_io.h"
#include "core/io/textured_glb_writer.h"
#include "core/pipeline/lens_job.h"

namespace volspline::cli {

namespace {

pipeline::LensMethod parse_method(const std::string& text) {
  if (text == "metric") return pipeline::LensMethod::Metric;
  if (text == "fisheye") return pipeline::LensMethod::Fisheye;
  if (text == "bifocal") return pipeline::LensMethod::Bifocal;
  if (text == "zoom") return pipeline::LensMethod::Zoom;
  throw UsageError("--method expects metric, fisheye, bifocal or zoom, got '" + text + "'");
}

// OBJ with texture coordinates: vertex (x, y, 0) in output pixels, vt normalized to the input
// image with v up, as OBJ viewers expect.
std::string textured_obj(const pipeline::LensResult& r, int width, int height) {
  std::ostringstream out;
  out.precision(17);
  out << "# volspline lens: flattened textured mesh (output pixels; vt over the input image)\n";
  for (Eigen::Index v = 0; v < r.positions.rows(); ++v) out << "v " << r.positions(v, 0) << ' ' << r.positions(v, 1) << " 0\n";
  for (Eigen::Index v = 0; v < r.texture.rows(); ++v)
    out << "vt " << r.texture(v, 0) / width << ' ' << 1.0 - r.texture(v, 1) / height << '\n';
  for (Eigen::Index t = 0; t < r.triangles.rows(); ++t) {
    out << 'f';
    for (int k = 0; k < 3; ++k) out << ' ' << r.triangles(t, k) + 1 << '/' << r.triangles(t, k) + 1;
    out << '\n';
  }
  return out.str();
}

}  // namespace

// Longer than the guide's ~120 lines on purpose: a flat driver (the option table, flags →
// options, the job, the outputs) with nothing to reuse; split, every part would take the parsed
// arguments and the output list along.
int run_lens(const std::vector<std::string>& argv_in) {
  const std::vector<OptionSpec> specs = with_job_options({
      {"output", "FILE", "output PNG (also -o); required"},
      {"roi", "SPEC",
       "region (pixels): circle:CX,CY,R | rect:X,Y,W,H | polygon:X1,Y1,... | mask:MASK.png; default a centred "
       "circle, radius min(width, height)/4",
       true},
      {"magnification", "M", "wanted linear magnification at each ROI centre, in (1, 16] (default 2)"},
      {"height", "H", "lens height h0 in ROI inscribed radii, instead of --magnification (metric only)"},
      {"alpha", "A", "metric blend, 0 rigid .. 1 conformal (Eq. 6.8; default 0)"},
      {"grid", "N", "grid vertices along the longer image side, >= 4 (default 100)"},
      {"square-boundary", "", "pin only the image border (thesis boundary control); default pins the far context too"},
      {"band", "B", "free context band around each ROI, in ROI radii (default 0.75)"},
      {"method", "NAME", "metric | fisheye | bifocal | zoom (default metric)"},
      {"max-pixels", "N", "refuse images (and masks) of more pixels, checked on the header before decoding (default 67108864)"},
      {"mesh-out", "FILE", "flattened textured mesh, .obj (with texture coordinates) or .glb (y up, UVs, the image embedded)"},
  }, "accepted for scripts; the lens runs on one thread");
  const Args args = parse_args(argv_in, specs);
  if (print_help_if_asked(args, "volspline lens IMAGE.png -o OUT.png [--roi SPEC ...] [options]",
                          "Focus+context magnification lens (thesis ch. 6): the ROIs are lifted to a 3D lens\n"
                          "mesh, textured harmonically and flattened back to the plane preserving a blend of\n"
                          "its rigid and conformal metric; the result is rendered to OUT.png. The baselines\n"
                          "fisheye, bifocal and zoom use the same grid, ROIs and measured magnification.",
                          specs))
    return 0;
  if (args.positional.size() != 1) throw UsageError("expects exactly one IMAGE (see --help)");
  if (!args.has("output")) throw UsageError("missing -o OUT.png");
  const std::string output = args.get("output");
  if (io::file_extension(output) != "png") throw UsageError("-o must name a .png file, got '" + output + "'");
  const std::string mesh_out = args.get("mesh-out");
  if (!mesh_out.empty() && io::file_extension(mesh_out) != "obj" && io::file_extension(mesh_out) != "glb")
    throw UsageError("--mesh-out must name a .obj or .glb file, got '" + mesh_out + "'");

  pipeline::LensOptions options;
  options.method = parse_method(args.get("method", "metric"));
  options.magnification = args.get_double("magnification", options.magnification);
  if (args.has("height")) {
    options.height = args.get_double("height", 0.0);
    if (!(options.height > 0)) throw UsageError("--height must be > 0, got '" + args.get("height") + "'");
  }
  options.alpha = args.get_double("alpha", options.alpha);
  options.grid = args.get_int("grid", options.grid);
  options.band = args.get_double("band", options.band);
  if (args.has("square-boundary")) options.boundary = pipeline::LensBoundary::Square;

  pipeline::LensInput input;
  input.name = args.positional[0];
  OutputFiles files;
  files.input(input.name);
  std::vector<lens::RoiSpec> specs_in;
  for (const std::string& text : args.get_all("roi")) {
    specs_in.push_back(lens::parse_roi_spec(text));
    if (!specs_in.back().mask_path.empty()) files.input(specs_in.back().mask_path);
  }
  files.output("-o", output);
  if (!mesh_out.empty()) files.output("--mesh-out", mesh_out);
  if (args.has("stats-json")) files.output("--stats-json", args.get("stats-json"));
  io::ImageLimits limits;
  if (args.has("max-pixels")) {
    const double max_pixels = args.get_double("max-pixels", 0.0);
    if (!(max_pixels >= 1) || max_pixels != std::floor(max_pixels) || max_pixels > 9e15)
      throw UsageError("--max-pixels expects a positive integer, got '" + args.get("max-pixels") + "'");
    limits.max_pixels = static_cast<std::int64_t>(max_pixels);
  }
  input.image = io::read_image(input.name, limits);
  for (lens::RoiSpec& spec : specs_in) {
    if (!spec.mask_path.empty()) spec.roi.mask = io::read_image(spec.mask_path, limits);
    input.rois.push_back(std::move(spec.roi));
  }
  if (input.rois.empty()) {
    // The default ROI: a circle at the image centre, a quarter of the shorter side in radius.
    const double w = input.image.width, h = input.image.height;
    input.rois.push_back(lens::parse_roi_spec("circle:" + std::to_string(w / 2) + "," + std::to_string(h / 2) + "," +
                                              std::to_string(std::min(w, h) / 4))
                             .roi);
  }

  ProgressBar bar(!args.has("quiet"));
  const pipeline::LensResult result = pipeline::run_lens(input, options, bar.progress());
  bar.finish();

  files.stage(output, io::encode_png(result.image));
  if (!mesh_out.empty()) {
    if (io::file_extension(mesh_out) == "obj") {
      files.stage(mesh_out, textured_obj(result, input.image.width, input.image.height));
    } else {
      io::TexturedPlane plane;
      plane.positions = result.positions;
      plane.texture = result.texture;
      plane.triangles = result.triangles;
      plane.output_height = input.image.height;  // the output has the input's size
      plane.texture_width = input.image.width;
      plane.texture_height = input.image.height;
      plane.texture_png = io::encode_png(input.image);
      files.stage(mesh_out, io::serialize_textured_glb(plane));
    }
  }
  const pipeline::LensStats& s = result.stats;
  if (args.has("stats-json")) {
    nlohmann::ordered_json j;
    j["input"] = input.name;
    j["method"] = args.get("method", "metric");
    j["magnification_requested"] = options.magnification;
    j["magnification_center"] = s.magnification_center;
    j["magnification_per_roi"] = s.magnification_per_roi;
    j["magnification_limited"] = s.magnification_limited;
    j["distortion_sum"] = s.distortion_sum;
    j["distortion_max"] = s.distortion_max;
    j["distortion_sum_focus"] = s.distortion_sum_focus;
    j["distortion_max_focus"] = s.distortion_max_focus;
    j["flipped_triangles"] = s.flipped_triangles;
    j["iterations"] = s.iterations;
    j["converged"] = s.converged;
    j["height"] = s.height;
    j["height_scale_per_roi"] = s.height_scale_per_roi;
    j["baseline_parameter"] = s.baseline_parameter;
    j["alpha"] = options.alpha;
    j["grid"] = options.grid;
    j["vertices"] = s.vertices;
    j["triangles"] = s.triangles;
    j["ms_total"] = s.ms_total;
    j["ms_calibration"] = s.ms_calibration;
    j["ms_mesh"] = s.ms_mesh;
    j["ms_factorize"] = s.ms_factorize;
    j["ms_per_iteration"] = s.ms_per_iteration;
    j["ms_render"] = s.ms_render;
    files.stage(args.get("stats-json"), j.dump(2) + "\n");
  }
  files.commit();
  if (!args.has("quiet"))
    std::fprintf(stderr, "lens: magnification %.3f, distortion max %.4f, %d flipped, %d iterations, %.1f ms\n",
                 s.magnification_center, s.distortion_max, s.flipped_triangles, s.iterations, s.ms_total);
  if (s.magnification_limited)
    std::fprintf(stderr, "lens: magnification %.2f asked, at most %.2f here without folding the image\n",
                 s.magnification_requested, s.magnification_center);
  return 0;
}

}  // namespace volspline::cli
