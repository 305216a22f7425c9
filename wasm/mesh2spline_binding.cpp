// SPDX-License-Identifier: MIT
#include "wasm/mesh2spline_binding.h"

#include <cstdint>
#include <optional>
#include <vector>

#include "core/common/error.h"
#include "core/io/glb_lines_writer.h"
#include "core/io/bezier_vtu_writer.h"
#include "core/io/gpc_spline_io.h"
#include "core/io/gpc_writers.h"
#include "core/io/mesh_io.h"
#include "core/io/spline_json.h"
#include "core/io/vtu_writer.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_report.h"
#include "core/pipeline/gpc_mesh2spline.h"
#include "core/pipeline/mesh2spline_job.h"
#include "core/polycube/solid_decomposition.h"
#include "core/spline/gpc_boundary_tessellation.h"
#include "core/spline/gpc_spline_cut.h"
#include "wasm/guarded.h"
#include "wasm/js_values.h"
#include "wasm/spline_preview.h"

namespace volspline::wasm {

using emscripten::val;

namespace {

pipeline::Mesh2SplineOptions job_options_from_js(const val& o) {
  pipeline::Mesh2SplineOptions options;
  options.max_rms_rel = number_option(o, "max_rms_rel", options.max_rms_rel);
  options.max_control_points = integer_option(o, "max_control_points", options.max_control_points, -1000000000, 1000000000);
  options.max_levels = integer_option(o, "max_levels", options.max_levels, -1000, 1000);
  options.initial_cells = integer_option(o, "initial_cells", options.initial_cells, -1000000, 1000000);
  options.grid_nodes = integer_option(o, "grid_nodes", options.grid_nodes, -1000000, 1000000);
  options.smoothing = number_option(o, "smoothing", options.smoothing);
  options.measure_samples = integer_option(o, "measure_samples", options.measure_samples, -1000000, 1000000);
  options.seed = static_cast<std::uint64_t>(integer_option(o, "seed", 1, 0, 2000000000));
  // The keys below name their option in the message; run_mesh2spline checks every range again.
  options.max_surface_error_rel = number_option(o, "max_surface_error_rel", options.max_surface_error_rel);
  if (!(options.max_surface_error_rel > 0.0))
    throw Error("option 'max_surface_error_rel': expected a number > 0 (fraction of the bounding-box diagonal)");
  options.area_balance_iterations =
      integer_option(o, "area_balance_iterations", options.area_balance_iterations, 0, 20);
  options.min_scaled_jacobian = number_option(o, "min_scaled_jacobian", options.min_scaled_jacobian);
  if (!(options.min_scaled_jacobian >= 0.0 && options.min_scaled_jacobian <= 0.5))
    throw Error("option 'min_scaled_jacobian': the Jacobian repair target must be 0 (no repair) or in (0, 0.5]");
  integer_option(o, "threads", 1, 1, 1024);  // accepted and checked; the job runs on one thread
  if (bool_option(o, "compare_uniform", false))
    options.compare_uniform = pipeline::Mesh2SplineOptions::CompareUniform::On;
  if (!bool_option(o, "untangle", true)) options.untangle = pipeline::Mesh2SplineOptions::Untangle::Off;
  const std::string fit = string_option(o, "fit", "grid");
  if (fit == "grid") options.fit = pipeline::Mesh2SplineFit::Grid;
  else if (fit == "meshless") options.fit = pipeline::Mesh2SplineFit::Meshless;
  else throw Error("option 'fit': unknown '" + fit + "' (grid, meshless)");
  const std::string weights = string_option(o, "weights", "meanvalue");
  if (weights == "meanvalue") options.weights = param::SurfaceWeights::MeanValue;
  else if (weights == "cotan") options.weights = param::SurfaceWeights::Cotan;
  else throw Error("option 'weights': unknown '" + weights + "' (meanvalue, cotan)");
  options.corners = corner_ids_option(o);
  return options;  // ranges are checked by run_mesh2spline
}

val bytes_to_js(const std::string& bytes) {
  return uint8_array(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

val cut_to_js(const SplineCut& cut, int axis, double position) {
  val out = val::object();
  out.set("axis", axis);
  out.set("position", position);
  out.set("positions", float32_array(cut.xyz.data(), cut.xyz.size()));
  out.set("triangles", uint32_array(cut.triangles.data(), cut.triangles.size()));
  out.set("scaled_jacobian", float32_array(cut.scaled_jacobian.data(), cut.scaled_jacobian.size()));
  out.set("uvw", float32_array(cut.uvw.data(), cut.uvw.size()));
  out.set("min_scaled_jacobian", cut.min_scaled_jacobian);
  return out;
}

void check_cut(int axis, double position, int samples) {
  if (axis < 0 || axis > 2) throw Error("cut axis must be 0, 1 or 2, got " + std::to_string(axis));
  if (!(position >= 0 && position <= 1)) throw Error("cut position must be in [0, 1]");
  if (samples < 2 || samples > 257) throw Error("cut samples must be in [2, 257], got " + std::to_string(samples));
}

// The keys both kinds of job report first, in the CLI's order.
val fit_stats_to_js(const pipeline::Mesh2SplineStats& s, const std::string& name, const std::string& fit) {
  val out = val::object();
  out.set("input", name);
  out.set("fit", fit);
  out.set("rms_rel", s.rms_rel);
  out.set("max_rel", s.max_rel);
  out.set("hausdorff_rel", s.hausdorff_rel);
  out.set("rms_geo_rel", s.rms_geo_rel);
  out.set("control_points", s.control_points);
  out.set("levels", s.levels);
  return out;
}

// The det J certificate's keys (both kinds of job, as the CLI's add_certificate_json).
void add_certificate_to_js(val& out, const pipeline::Mesh2SplineStats& s) {
  out.set("jacobian_certified_fraction", s.jacobian_certified_fraction);
  out.set("det_j_lower_bound_rel", s.det_j_lower_bound_rel);
  out.set("certificate_cells", s.certificate_cells);
  val uncertified = val::array();
  for (const spline::UncertifiedCell& u : s.uncertified_cells) {
    val cell = val::object();
    cell.set("cuboid", u.cuboid);
    cell.set("cell", u.cell);
    val lo = val::array(), hi = val::array();
    for (int a = 0; a < 3; ++a) lo.call<void>("push", u.uvw_min[a]), hi.call<void>("push", u.uvw_max[a]);
    cell.set("uvw_min", lo);
    cell.set("uvw_max", hi);
    cell.set("status", std::string(u.bound.status == spline::JacobianCellStatus::Negative ? "negative" : "undecided"));
    cell.set("det_j_lower_bound_rel", u.bound.det_j_lower_bound_rel);
    uncertified.call<void>("push", cell);
  }
  out.set("uncertified_cells", uncertified);
}

val stats_to_js(const pipeline::Mesh2SplineStats& s, const std::string& name, const std::string& fit) {
  val out = fit_stats_to_js(s, name, fit);
  add_certificate_to_js(out, s);
  out.set("min_scaled_jacobian", s.min_scaled_jacobian);
  out.set("jacobian_samples", double(s.jacobian_samples));
  out.set("negative_jacobian_fraction", s.negative_jacobian_fraction);
  out.set("semi_standard_max_error", s.semi_standard_max_error);
  out.set("cuboids", s.cuboids);
  out.set("flipped_triangles", s.flipped_triangles);
  out.set("squeeze_rounds", s.squeeze_rounds);
  out.set("grid_inverted_hexes", s.grid_inverted_hexes);
  out.set("grid_min_scaled_jacobian", s.grid_min_scaled_jacobian);
  out.set("samples", s.samples);
  out.set("min_corner_distance_rel", s.min_corner_distance_rel);
  out.set("negative_jacobian_fraction_fit", s.negative_jacobian_fraction_fit);
  out.set("repaired_control_points", s.repaired_control_points);
  out.set("untangled_control_points", s.untangled_control_points);
  out.set("creased_control_points", s.creased_control_points);
  // null when not computed (compare_uniform off) or not reached, as in the CLI's stats JSON.
  out.set("uniform_control_points", s.uniform_control_points >= 0 ? val(s.uniform_control_points) : val::null());
  out.set("uniform_rms_rel", s.uniform_rms_rel);
  val corners = val::array();
  for (int c : s.corners) corners.call<void>("push", c);
  out.set("corners", corners);
  out.set("times_s", stage_times_object(s.times_s));
  return out;
}

val vector3(const Eigen::Vector3d& v) {
  val out = val::array();
  for (int k = 0; k < 3; ++k) out.call<void>("push", v[k]);
  return out;
}

val input_to_js(const mesh::TriangleMesh& input) {
  val in = val::object();
  const std::vector<float> positions(input.positions.data(), input.positions.data() + input.positions.size());
  in.set("positions", float32_array(positions.data(), positions.size()));
  const std::vector<std::uint32_t> triangles(input.triangles.data(), input.triangles.data() + input.triangles.size());
  in.set("triangles", uint32_array(triangles.data(), triangles.size()));
  in.set("bbox_min", vector3(input.positions.colwise().minCoeff().transpose()));
  in.set("bbox_max", vector3(input.positions.colwise().maxCoeff().transpose()));
  return in;
}

// The genus of a closed surface, 0 if it is not one (run_mesh2spline then names the problem).
int surface_genus(const mesh::TriangleMesh& input, const std::string& name) {
  try {
    return mesh::analyze_mesh(mesh::HalfedgeMesh::build(input, name)).genus;
  } catch (const Error&) {
    return 0;
  }
}

bool has_option(const val& o, const char* key) { return !o.isUndefined() && !o.isNull() && !o[key].isUndefined(); }

// The multi-cuboid job's options from the same keys, as the CLI maps its flags; max_levels and
// max_surface_error_rel only when given (their defaults differ from the single cuboid's).
pipeline::GpcMesh2SplineOptions gpc_job_options_from_js(const val& o, const pipeline::Mesh2SplineOptions& m) {
  if (m.fit != pipeline::Mesh2SplineFit::Grid)
    throw Error("option 'fit': a solid of genus > 0 is fitted over its GPC grid map; 'meshless' needs genus 0");
  pipeline::GpcMesh2SplineOptions options;
  options.max_rms_rel = m.max_rms_rel;
  options.max_control_points = m.max_control_points;
  if (has_option(o, "max_levels")) options.max_levels = m.max_levels;
  if (has_option(o, "max_surface_error_rel")) options.max_surface_error_rel = m.max_surface_error_rel;
  if (bool_option(o, "adaptive_knots", false)) options.refinement = pipeline::GpcMesh2SplineOptions::Refinement::Adaptive;
  if (bool_option(o, "hierarchical", false))
    options.refinement = pipeline::GpcMesh2SplineOptions::Refinement::Hierarchical;
  if (bool_option(o, "uniform_knots", false)) options.refinement = pipeline::GpcMesh2SplineOptions::Refinement::Uniform;
  options.fit_damping = number_option(o, "fit_damping", options.fit_damping);
  options.adaptive_growth = number_option(o, "adaptive_growth", options.adaptive_growth);
  options.hierarchy_depth = integer_option(o, "hierarchy_depth", options.hierarchy_depth, -1000000, 1000000);
  options.surface_weight = number_option(o, "surface_weight", options.surface_weight);
  options.measure_lattice = integer_option(o, "measure_lattice", options.measure_lattice, -1000000, 1000000);
  if (m.untangle == pipeline::Mesh2SplineOptions::Untangle::Off)
    options.untangle = pipeline::GpcMesh2SplineOptions::Untangle::Off;
  options.initial_cells = m.initial_cells;
  options.measure_samples = m.measure_samples;
  options.seed = m.seed;
  options.gpc.grid.area_balance_iterations = m.area_balance_iterations;
  options.gpc.grid.target_nodes = integer_option(o, "gpc_grid_nodes", options.gpc.grid.target_nodes, 64, 20000000);
  if (!bool_option(o, "padding", true)) options.gpc.grid.padding = param::GpcGridOptions::Padding::Off;
  return options;  // ranges are checked by run_gpc_mesh2spline
}

val gpc_stats_to_js(const pipeline::Mesh2SplineStats& s, const std::string& name,
                    pipeline::GpcMesh2SplineOptions::Refinement refinement) {
  val out = fit_stats_to_js(s, name, "grid");
  out.set("knot_refinement", std::string(pipeline::refinement_name(refinement)));
  val history = val::array();
  for (const pipeline::Mesh2SplineStats::Level& l : s.level_history) {
    val level = val::object();
    level.set("control_points", l.control_points);
    level.set("rms_rel", l.rms_rel);
    level.set("surface_max_rel", l.surface_max_rel);
    history.call<void>("push", level);
  }
  out.set("level_history", history);
  add_certificate_to_js(out, s);
  out.set("min_scaled_jacobian", s.min_scaled_jacobian);
  out.set("negative_jacobian_fraction", s.negative_jacobian_fraction);
  out.set("jacobian_samples", double(s.jacobian_samples));
  out.set("lattice_negative_fraction", s.lattice_negative_fraction);
  out.set("lattice_samples", double(s.lattice_samples));
  out.set("semi_standard_max_error", s.semi_standard_max_error);
  out.set("genus", s.genus);
  out.set("t_shapes", s.t_shapes);
  out.set("cuboids", s.cuboids);
  out.set("ill_points", s.ill_points);
  out.set("interfaces", s.interfaces);
  out.set("continued_interfaces", s.continued_interfaces);
  out.set("interface_gap_rel", s.interface_gap_rel);
  out.set("interface_normal_jump_deg", s.interface_normal_jump_deg);
  out.set("flipped_triangles", s.flipped_triangles);
  out.set("squeeze_rounds", s.squeeze_rounds);
  out.set("hierarchy_depth", s.hierarchy_depth);
  out.set("centroid_samples", s.centroid_samples);
  out.set("refit_dropped_nodes", s.refit_dropped_nodes);
  out.set("grid_inverted_hexes", s.grid_inverted_hexes);
  out.set("grid_min_scaled_jacobian", s.grid_min_scaled_jacobian);
  val retries = val::object();
  for (const auto& [key, value] : s.domain_retries) retries.set(key, value);
  out.set("domain_retries", retries);
  out.set("samples", s.samples);
  out.set("untangled_control_points", s.untangled_control_points);
  out.set("untangle_surface_shift_rel", s.untangle_surface_shift_rel);
  if (!s.untangle_path.empty()) {
    out.set("untangle_path", s.untangle_path);
    out.set("certificate_passes", s.certificate_passes);
    out.set("local_certificate_passes", s.local_certificate_passes);
  }
  out.set("times_s", stage_times_object(s.times_s));
  return out;
}

val gpc_cut_to_js(const spline::GpcSplineCut& cut, int axis, double position) {
  val out = val::object();
  out.set("axis", axis);
  out.set("position", position);
  out.set("positions", float32_array(cut.xyz.data(), cut.xyz.size()));
  out.set("triangles", uint32_array(cut.triangles.data(), cut.triangles.size()));
  out.set("scaled_jacobian", float32_array(cut.scaled_jacobian.data(), cut.scaled_jacobian.size()));
  out.set("cuboid", uint32_array(cut.cuboid.data(), cut.cuboid.size()));
  out.set("uvw", float32_array(cut.uvw.data(), cut.uvw.size()));
  out.set("min_scaled_jacobian", cut.min_scaled_jacobian);
  return out;
}

// mesh2spline of a solid of genus > 0 (run_gpc_mesh2spline), in the genus-0 result's shape; the
// boundary and lines also name each point's cuboid and carry its colour (io::segment_colour).
// folded_one: the stats of a genus-0 solid's folded one-cuboid spline, or null; with them, the
// result is undefined where no GPC is built or its spline does not fold less (one cuboid kept).
val gpc_mesh2spline(const mesh::TriangleMesh& input, const std::string& name, const val& options,
                    const pipeline::Mesh2SplineOptions& m, const val& progress,
                    const pipeline::Mesh2SplineStats* folded_one = nullptr) {
  const pipeline::GpcMesh2SplineOptions job = gpc_job_options_from_js(options, m);
  const int preview_samples = integer_option(options, "preview_samples", 25, 2, 129);
  const int preview_lines = integer_option(options, "preview_lines", 9, 2, 65);
  const int cut_axis = integer_option(options, "cut_axis", 2, 0, 2);
  const double cut_position = number_option(options, "cut_position", 0.5);
  const int cut_samples = integer_option(options, "cut_samples", 41, 2, 257);
  // VTU: the exact Bézier cells, or straight hexes on a vtu_cells lattice when that is given.
  const int vtu_cells = has_option(options, "vtu_cells") ? integer_option(options, "vtu_cells", 24, 1, 64) : 0;
  const bool outputs = bool_option(options, "outputs", true);
  std::optional<pipeline::GpcMesh2SplineResult> run;
  try {
    run = pipeline::run_gpc_mesh2spline(input, name, job, progress_from_js(progress));
  } catch (const polycube::DecompositionError& e) {
    if (folded_one) return val::undefined();
    // The CLI's exit 1: the input was fine, the construction was not.
    return failure(std::string("mesh2spline failed: ") + e.what());
  }
  const pipeline::GpcMesh2SplineResult& result = *run;
  if (folded_one && !pipeline::gpc_folds_less(result.stats, *folded_one)) return val::undefined();

  val out = val::object();
  out.set("ok", true);
  out.set("domain", std::string("gpc"));
  out.set("stats", gpc_stats_to_js(result.stats, name, job.refinement));
  out.set("input", input_to_js(input));

  const spline::GpcBoundaryTessellation b = spline::tessellate_gpc_boundary(result.spline, preview_samples, preview_lines);
  std::vector<float> colours;
  colours.reserve(3 * b.surface_cuboid.size());
  for (std::uint32_t c : b.surface_cuboid)
    for (float x : io::segment_colour(static_cast<int>(c))) colours.push_back(x);
  val boundary = val::object();
  boundary.set("positions", float32_array(b.surface_xyz.data(), b.surface_xyz.size()));
  boundary.set("uvw", float32_array(b.surface_uvw.data(), b.surface_uvw.size()));
  boundary.set("triangles", uint32_array(b.surface_triangles.data(), b.surface_triangles.size()));
  boundary.set("cuboid", uint32_array(b.surface_cuboid.data(), b.surface_cuboid.size()));
  boundary.set("colours", float32_array(colours.data(), colours.size()));
  out.set("boundary", boundary);
  val lines = val::object();
  lines.set("positions", float32_array(b.line_xyz.data(), b.line_xyz.size()));
  lines.set("uvw", float32_array(b.line_uvw.data(), b.line_uvw.size()));
  lines.set("cuboid", uint32_array(b.line_cuboid.data(), b.line_cuboid.size()));
  out.set("lines", lines);
  const Eigen::MatrixXd& points = result.spline.points();
  std::vector<float> control;
  control.reserve(points.rows() * 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (int d = 0; d < 3; ++d) control.push_back(static_cast<float>(points(i, d)));
  out.set("control_points", float32_array(control.data(), control.size()));
  // Each control point's anchor as a fraction of its cuboid's box: the view clips them by the cut.
  std::vector<float> control_uvw;
  control_uvw.reserve(points.rows() * 3);
  for (int i = 0; i < result.spline.num_functions(); ++i) {
    const spline::GpcAnchor& anchor = result.spline.anchor(i);
    const auto& size = result.spline.domain().cuboids[anchor.cuboid].size;
    for (int a = 0; a < 3; ++a) control_uvw.push_back(static_cast<float>(anchor.uvw(a) / size[a]));
  }
  out.set("control_uvw", float32_array(control_uvw.data(), control_uvw.size()));
  out.set("cut", gpc_cut_to_js(spline::gpc_spline_cut(result.spline, cut_axis, cut_position, cut_samples), cut_axis,
                               cut_position));
  if (outputs) {
    out.set("spline_json", bytes_to_js(io::serialize_gpc_spline_json(result.spline)));
    out.set("glb", bytes_to_js(io::serialize_gpc_spline_glb(result.spline)));
    out.set("vtu", bytes_to_js(vtu_cells > 0 ? io::serialize_gpc_spline_vtu(result.spline, vtu_cells)
                                              : io::serialize_gpc_bezier_vtu(result.spline)));
  }
  return out;
}

}  // namespace

val mesh2spline(const val& bytes, const std::string& name, const val& options, const val& progress) {
  return guarded([&] {
    const pipeline::Mesh2SplineOptions job = job_options_from_js(options);
    const int preview_samples = integer_option(options, "preview_samples", 25, 2, 129);
    const int preview_lines = integer_option(options, "preview_lines", 9, 2, 65);
    const int cut_axis = integer_option(options, "cut_axis", 2, 0, 2);
    const double cut_position = number_option(options, "cut_position", 0.5);
    const int cut_samples = integer_option(options, "cut_samples", 41, 2, 257);
    const int vtu_cells = has_option(options, "vtu_cells") ? integer_option(options, "vtu_cells", 24, 1, 64) : 0;
    const bool outputs = bool_option(options, "outputs", true);
    check_cut(cut_axis, cut_position, cut_samples);

    const mesh::TriangleMesh input =
        io::parse_mesh(bytes_from_js(bytes, "mesh '" + name + "'"), io::mesh_format_from_path(name), name);
    if (surface_genus(input, name) > 0) return gpc_mesh2spline(input, name, options, job, progress);
    // A squeezed one-cuboid map goes through the GPC with the limbs as caps, as on the CLI.
    pipeline::Mesh2SplineOptions one = job;
    if (!bool_option(options, "one_cuboid", false)) one.squeezed = pipeline::Mesh2SplineOptions::Squeezed::Refuse;
    std::optional<pipeline::Mesh2SplineResult> run;
    try {
      run = pipeline::run_mesh2spline(input, name, one, progress_from_js(progress));
    } catch (const pipeline::SqueezedOneCuboid&) {
      return gpc_mesh2spline(input, name, options, job, progress);
    }
    const pipeline::Mesh2SplineResult& result = *run;
    // A folded one-cuboid spline is made over the GPC too, as on the CLI.
    if (!bool_option(options, "one_cuboid", false) && pipeline::one_cuboid_folds(one, result.stats)) {
      val over_gpc = gpc_mesh2spline(input, name, options, job, progress, &result.stats);
      if (!over_gpc.isUndefined()) return over_gpc;
    }

    val out = val::object();
    out.set("ok", true);
    out.set("domain", std::string("cuboid"));
    out.set("stats", stats_to_js(result.stats, name, job.fit == pipeline::Mesh2SplineFit::Grid ? "grid" : "meshless"));
    out.set("input", input_to_js(input));

    const SplinePreview preview = spline_preview(result.spline, preview_samples, preview_lines);
    val boundary = val::object();
    boundary.set("positions", float32_array(preview.surface_xyz.data(), preview.surface_xyz.size()));
    boundary.set("uvw", float32_array(preview.surface_uvw.data(), preview.surface_uvw.size()));
    boundary.set("triangles", uint32_array(preview.surface_triangles.data(), preview.surface_triangles.size()));
    out.set("boundary", boundary);
    val lines = val::object();
    lines.set("positions", float32_array(preview.line_xyz.data(), preview.line_xyz.size()));
    lines.set("uvw", float32_array(preview.line_uvw.data(), preview.line_uvw.size()));
    out.set("lines", lines);
    out.set("control_points", float32_array(preview.control_xyz.data(), preview.control_xyz.size()));
    out.set("cut", cut_to_js(wasm::spline_cut(result.spline, cut_axis, cut_position, cut_samples), cut_axis, cut_position));

    if (outputs) {
      out.set("spline_json", bytes_to_js(io::serialize_spline_json(result.spline)));
      out.set("glb", bytes_to_js(io::serialize_spline_glb(result.spline)));
      out.set("vtu", bytes_to_js(vtu_cells > 0 ? io::serialize_spline_vtu(result.spline, {vtu_cells, vtu_cells, vtu_cells})
                                                : io::serialize_bezier_vtu(result.spline)));
    }
    return out;
  });
}

val spline_cut(const val& spline_json, int axis, double position, int samples) {
  return guarded([&] {
    check_cut(axis, position, samples);
    const std::string text = bytes_from_js(spline_json, "spline JSON");
    if (io::is_gpc_spline_json(text)) {
      const spline::GpcSpline gpc = io::parse_gpc_spline_json(text, "spline JSON");
      if (gpc.dimension() != 3)
        throw Error("spline JSON: a cut needs a geometric spline (dimension 3), got dimension " +
                    std::to_string(gpc.dimension()));
      val out = gpc_cut_to_js(spline::gpc_spline_cut(gpc, axis, position, samples), axis, position);
      out.set("ok", true);
      return out;
    }
    const spline::TSpline spline = io::parse_spline_json(text, "spline JSON");
    if (spline.dimension() != 3)
      throw Error("spline JSON: a cut needs a geometric spline (dimension 3), got dimension " +
                  std::to_string(spline.dimension()));
    val out = cut_to_js(wasm::spline_cut(spline, axis, position, samples), axis, position);
    out.set("ok", true);
    return out;
  });
}

}  // namespace volspline::wasm
