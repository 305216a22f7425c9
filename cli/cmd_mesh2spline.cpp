// SPDX-License-Identifier: MIT
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/corners_file.h"
#include "cli/output_files.h"
#include "cli/progress_bar.h"
#include "cli/stage_times_json.h"
#include "core/io/bezier_extraction_json.h"
#include "core/io/bezier_vtu_writer.h"
#include "core/io/file_bytes.h"
#include "core/io/gismo_xml_writer.h"
#include "core/io/glb_lines_writer.h"
#include "core/io/mesh_io.h"
#include "core/io/mfem_mesh_writer.h"
#include "core/io/spline_json.h"
#include "core/io/vtu_writer.h"
#include "core/io/gpc_spline_io.h"
#include "core/pipeline/gpc_mesh2spline.h"
#include "core/pipeline/mesh2spline_job.h"
#include "core/pipeline/solid_mesh.h"
#include "core/polycube/solid_decomposition.h"
#include "core/spline/bspline_multipatch.h"

namespace volspline::cli {

namespace {

// The keys both kinds of mesh2spline stats report first, in this order (as the wasm binding's
// fit_stats_to_js).
nlohmann::ordered_json fit_stats_json(const pipeline::Mesh2SplineStats& s, const std::string& path, const std::string& fit) {
  nlohmann::ordered_json j;
  j["input"] = path;
  j["fit"] = fit;
  j["rms_rel"] = s.rms_rel;
  j["max_rel"] = s.max_rel;
  j["hausdorff_rel"] = s.hausdorff_rel;
  j["rms_geo_rel"] = s.rms_geo_rel;
  j["control_points"] = s.control_points;
  j["levels"] = s.levels;
  return j;
}

// The det J certificate's keys (both kinds of job, after the fit keys).
void add_certificate_json(nlohmann::ordered_json& j, const pipeline::Mesh2SplineStats& s) {
  j["jacobian_certified_fraction"] = s.jacobian_certified_fraction;
  j["det_j_lower_bound_rel"] = s.det_j_lower_bound_rel;
  j["certificate_cells"] = s.certificate_cells;
  nlohmann::ordered_json uncertified = nlohmann::ordered_json::array();
  for (const spline::UncertifiedCell& u : s.uncertified_cells) {
    uncertified.push_back({{"cuboid", u.cuboid},
                           {"cell", u.cell},
                           {"uvw_min", {u.uvw_min[0], u.uvw_min[1], u.uvw_min[2]}},
                           {"uvw_max", {u.uvw_max[0], u.uvw_max[1], u.uvw_max[2]}},
                           {"status", u.bound.status == spline::JacobianCellStatus::Negative ? "negative" : "undecided"},
                           {"det_j_lower_bound_rel", u.bound.det_j_lower_bound_rel}});
  }
  j["uncertified_cells"] = uncertified;
}

// The GPC job's options from the command line and the one-cuboid options already read.
pipeline::GpcMesh2SplineOptions gpc_options(const Args& args, const pipeline::Mesh2SplineOptions& m) {
  pipeline::GpcMesh2SplineOptions options;
  options.max_rms_rel = m.max_rms_rel;
  if (args.has("max-surface-error")) options.max_surface_error_rel = m.max_surface_error_rel;
  options.max_control_points = m.max_control_points;
  if (args.has("max-levels")) options.max_levels = m.max_levels;
  if (m.untangle == pipeline::Mesh2SplineOptions::Untangle::Off) options.untangle = pipeline::GpcMesh2SplineOptions::Untangle::Off;
  options.initial_cells = m.initial_cells;
  options.measure_samples = m.measure_samples;
  options.seed = m.seed;
  options.gpc.grid.area_balance_iterations = m.area_balance_iterations;
  options.squeezed_below = m.squeezed_below;
  if (args.has("no-padding")) options.gpc.grid.padding = param::GpcGridOptions::Padding::Off;
  if (args.has("no-refit")) options.refit_folded_nodes = false;
  if (args.has("adaptive-knots")) options.refinement = pipeline::GpcMesh2SplineOptions::Refinement::Adaptive;
  if (args.has("hierarchical")) options.refinement = pipeline::GpcMesh2SplineOptions::Refinement::Hierarchical;
  if (args.has("uniform-knots")) options.refinement = pipeline::GpcMesh2SplineOptions::Refinement::Uniform;
  if (args.has("compare-uniform")) options.compare_uniform = pipeline::GpcMesh2SplineOptions::CompareUniform::On;
  if (int(args.has("adaptive-knots")) + int(args.has("hierarchical")) + int(args.has("uniform-knots")) > 1)
    throw UsageError("--uniform-knots, --adaptive-knots and --hierarchical exclude each other");
  options.fit_damping = args.get_double("fit-damping", options.fit_damping);
  options.hierarchy_depth = args.get_int("hierarchy-depth", options.hierarchy_depth);
  if (args.has("hierarchy-depth") && options.hierarchy_depth < 1)  // 0 is the core's automatic depth
    throw UsageError("--hierarchy-depth must be in 1..6, got " + std::to_string(options.hierarchy_depth));
  options.adaptive_growth = args.get_double("knot-growth", options.adaptive_growth);
  options.surface_weight = args.get_double("surface-weight", options.surface_weight);
  if (args.has("centroid-samples") && args.has("vertex-samples"))
    throw UsageError("--centroid-samples and --vertex-samples exclude each other");
  if (args.has("centroid-samples")) options.surface_samples = pipeline::GpcMesh2SplineOptions::SurfaceSamples::VerticesAndCentroids;
  if (args.has("vertex-samples")) options.surface_samples = pipeline::GpcMesh2SplineOptions::SurfaceSamples::Vertices;
  options.measure_lattice = args.get_int("measure-lattice", options.measure_lattice);
  options.threads = args.get_int("threads", 1);
  options.certificate_rounds = args.get_int("certificate-rounds", options.certificate_rounds);
  const std::string start = args.get("untangle-start", "rounds");
  if (start == "passes")
    options.untangle_start = pipeline::GpcMesh2SplineOptions::UntangleStart::PassesFirst;
  else if (start != "rounds")
    throw UsageError("--untangle-start must be rounds or passes, got '" + start + "'");
  if (args.has("limbs")) options.gpc.limb_persistence = args.get_double("limbs", 0.0);
  options.gpc.grid.target_nodes = args.get_int("grid-nodes", options.gpc.grid.target_nodes);
  return options;
}

pipeline::GpcMesh2SplineResult run_gpc_job(const Args& args, const mesh::TriangleMesh& input, const std::string& path,
                                           const pipeline::GpcMesh2SplineOptions& options) {
  ProgressBar bar(!args.has("quiet"));
  pipeline::GpcMesh2SplineResult result = pipeline::run_gpc_mesh2spline(input, path, options, bar.progress());
  bar.finish();
  return result;
}

// Stages the GPC spline's outputs, commits them and prints the summary.
void write_gpc_outputs(const Args& args, const std::string& path, const pipeline::GpcMesh2SplineOptions& options,
                       const pipeline::GpcMesh2SplineResult& result, int vtk_cells, OutputFiles& files) {
  const std::string output = args.get("output");
  files.stage(output, io::serialize_gpc_spline_json(result.spline));
  if (args.has("vtk"))
    files.stage(args.get("vtk"), vtk_cells > 0 ? io::serialize_gpc_spline_vtu(result.spline, vtk_cells)
                                               : io::serialize_gpc_bezier_vtu(result.spline));
  if (args.has("glb")) files.stage(args.get("glb"), io::serialize_gpc_spline_glb(result.spline));
  if (args.has("gismo"))
    files.stage(args.get("gismo"), io::serialize_gismo_xml(spline::multipatch_from_gpc_spline(result.spline)));
  if (args.has("mfem")) files.stage(args.get("mfem"), io::serialize_mfem_mesh(spline::vertex_based_multipatch(result.spline)));
  if (args.has("bezier")) files.stage(args.get("bezier"), io::serialize_bezier_extraction_json(result.spline));
  const pipeline::Mesh2SplineStats& s = result.stats;
  if (args.has("stats-json")) {
    nlohmann::ordered_json j = fit_stats_json(s, path, "grid");
    j["knot_refinement"] = pipeline::refinement_name(options.refinement);
    nlohmann::ordered_json history = nlohmann::ordered_json::array();
    for (const auto& l : s.level_history)
      history.push_back({{"control_points", l.control_points}, {"rms_rel", l.rms_rel}, {"surface_max_rel", l.surface_max_rel}});
    j["level_history"] = history;
    add_certificate_json(j, s);
    j["min_scaled_jacobian"] = s.min_scaled_jacobian;
    j["negative_jacobian_fraction"] = s.negative_jacobian_fraction;
    j["jacobian_samples"] = s.jacobian_samples;
    j["lattice_negative_fraction"] = s.lattice_negative_fraction;
    j["lattice_samples"] = s.lattice_samples;
    j["semi_standard_max_error"] = s.semi_standard_max_error;
    j["genus"] = s.genus;
    j["t_shapes"] = s.t_shapes;
    j["cuboids"] = s.cuboids;
    j["ill_points"] = s.ill_points;
    j["interfaces"] = s.interfaces;
    j["continued_interfaces"] = s.continued_interfaces;
    if (options.compare_uniform == pipeline::GpcMesh2SplineOptions::CompareUniform::On) {
      j["uniform_control_points"] = s.uniform_control_points >= 0 ? nlohmann::ordered_json(s.uniform_control_points)
                                                                   : nlohmann::ordered_json(nullptr);
      j["uniform_rms_rel"] = s.uniform_rms_rel;
    }
    j["interface_gap_rel"] = s.interface_gap_rel;
    j["interface_normal_jump_deg"] = s.interface_normal_jump_deg;
    j["flipped_triangles"] = s.flipped_triangles;
    j["squeeze_rounds"] = s.squeeze_rounds;
    j["surface_least_density"] = std::isfinite(s.surface_least_density) ? nlohmann::ordered_json(s.surface_least_density) : nlohmann::ordered_json(nullptr);
    j["hierarchy_depth"] = s.hierarchy_depth;
    j["centroid_samples"] = s.centroid_samples;
    j["refit_dropped_nodes"] = s.refit_dropped_nodes;
    j["grid_inverted_hexes"] = s.grid_inverted_hexes;
    j["grid_min_scaled_jacobian"] = s.grid_min_scaled_jacobian;
    if (!s.domain_retries.empty()) j["domain_retries"] = s.domain_retries;
    j["samples"] = s.samples;
    j["untangled_control_points"] = s.untangled_control_points;
    j["untangle_surface_shift_rel"] = s.untangle_surface_shift_rel;
    if (!s.untangle_path.empty()) {
      j["untangle_path"] = s.untangle_path;
      j["certificate_passes"] = s.certificate_passes;
      j["local_certificate_passes"] = s.local_certificate_passes;
    }
    j["times_s"] = stage_times_json(s.times_s);
    files.stage(args.get("stats-json"), j.dump(2) + "\n");
  }
  files.commit();
  if (!args.has("quiet"))
    std::fprintf(stderr,
                 "mesh2spline: genus %d, %d cuboids, %d control points, %d levels, rms_rel %.3g, hausdorff_rel %.3g, "
                 "certified fold-free cells %.4g %% (%zu not), min scaled Jacobian %.3g at the Gauss points, "
                 "interface gap %.3g\n",
                 s.genus, s.cuboids, s.control_points, s.levels, s.rms_rel, s.hausdorff_rel,
                 100.0 * s.jacobian_certified_fraction, s.uncertified_cells.size(), s.min_scaled_jacobian,
                 s.interface_gap_rel);
}

// A solid of genus > 0: one spline over its generalized poly-cube (run_gpc_mesh2spline).
void run_gpc_mesh2spline_command(const Args& args, const mesh::TriangleMesh& input, const std::string& path,
                                 const pipeline::Mesh2SplineOptions& m, int vtk_cells, OutputFiles& files) {
  const pipeline::GpcMesh2SplineOptions options = gpc_options(args, m);
  write_gpc_outputs(args, path, options, run_gpc_job(args, input, path, options), vtk_cells, files);
}

// The genus of a valid closed solid, checked on a unit-box copy (0 if the box is degenerate:
// run_mesh2spline then names the problem).
int solid_genus(const mesh::TriangleMesh& input, const std::string& path) {
  if (input.num_vertices() == 0) return 0;
  mesh::TriangleMesh unit = input;
  const Eigen::RowVector3d lo = unit.positions.colwise().minCoeff(), hi = unit.positions.colwise().maxCoeff();
  const double diagonal = (hi - lo).norm();
  if (!(diagonal > 0.0) || !std::isfinite(diagonal)) return 0;
  unit.positions = (unit.positions.rowwise() - 0.5 * (lo + hi)) / diagonal;
  return pipeline::validate_solid_mesh(unit, path, "mesh2spline").report.genus;
}

}  // namespace

// Longer than the guide's ~120 lines on purpose: a flat driver (the option table, flags →
// options, the job, the outputs) with nothing to reuse; split, every part would take the parsed
// arguments and the output list along.
int run_mesh2spline(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = with_job_options({
      {"output", "OUT.json", "spline JSON file to write (required; also -o)"},
      {"vtk", "OUT.vtu", "the spline as VTK Bézier hexahedra (exact, one per knot-line cell) with the certified scaled_jacobian_min per cell"},
      {"vtk-linear", "N", "write --vtk as straight hexes sampled on an N^3 lattice instead (tools without Bézier cells)"},
      {"glb", "OUT.glb", "boundary surface of the spline with iso-parameter lines"},
      {"gismo", "OUT.xml", "G+Smo XML: a multipatch of TensorBSpline3 volumes (one per cuboid, exact) with interfaces and boundary"},
      {"mfem", "OUT.mesh", "MFEM NURBS mesh (patches form) of the same tensor B-spline patches"},
      {"bezier", "OUT.json", "the Bézier extraction operator per cell (control points, weights, per-cell extraction matrices)"},
      {"max-rms", "R", "stop refining at rms_rel <= R (fraction of the bbox diagonal; default 0.002)"},
      {"max-surface-error", "R", "also refine until every surface sample is within R of the mesh (fraction of the bbox diagonal; default 0.005; genus > 0: 0.008, 0 = rms only)"},
      {"max-control-points", "N", "no refinement beyond N control points (default 50000)"},
      {"max-levels", "L", "refinement levels after level 0 (default 4; genus > 0: knot refinements, default 14)"},
      {"fit", "grid|meshless", "grid: volumetric grid map + fit (§3.4.2); meshless: §4.3.2 (default grid)"},
      {"limbs", "P", "limb ends become caps when their branch is at least P of the shape's graph diameter long; genus 0: P > 0 sends the solid through the GPC as genus > 0 (default: 0.15 for genus > 0, off for genus 0)"},
      {"corners", "FILE", "8 corner vertex ids (cube corner c at (c&1, c>>1&1, c>>2&1)); default automatic"},
      {"weights", "meanvalue|cotan", "surface map weights (default meanvalue)"},
      {"area-balance", "N", "stretch-reweighting rounds of the surface map, 0 = plain Floater map (default 4)"},
      {"squeezed-below", "D", "widen the surface map where a vertex's linear parameter density is below D (thin tips: ears, tails, claws), 0 = off (default 0.1)"},
      {"repair-jacobian", "Q", "move interior control points until the scaled Jacobian is >= Q (0 = off, default; slow)"},
      {"initial-cells", "N", "spline cells along the longest cuboid axis at level 0 (default 4)"},
      {"compare-uniform", "", "also fit uniform B-splines to the same rms_rel (stats: uniform_control_points)"},
      {"no-untangle", "", "skip the untangling of folded interior control points after the fit (the thesis's plain fit)"},
      {"grid-nodes", "N", "genus > 0: about N volumetric grid nodes over all cuboids (default 24000, see volspline gpc)"},
      {"no-padding", "", "genus > 0: fit the cuboid grids without the padding layer under the surface (see volspline gpc)"},
      {"no-refit", "", "genus > 0: where cells stay uncertified, keep the fit (default: fit and untangle again without the grid nodes of inverted hexes, keep the better certificate; stats refit_dropped_nodes)"},
      {"adaptive-knots", "", "genus > 0: each level adds knot lines where the misfit is instead of dividing the spacing by 1.5"},
      {"hierarchical", "", "genus > 0 (default): past the uniform levels, split the functions at the surface samples beyond --max-surface-error and those holding the most misfit (T-spline refinement)"},
      {"uniform-knots", "", "genus > 0: every level divides the knot spacing by 1.5 (no T-spline splits)"},
      {"hierarchy-depth", "L", "genus > 0, --hierarchical: split functions at most L dyadic levels below the last uniform level (1..6; default 3, or 6 where a cuboid's surface map is squeezed: squeeze_rounds > 0 or surface_least_density below --squeezed-below)"},
      {"fit-damping", "D", "genus > 0: pull of every level's least squares towards the previous level's spline, relative to the mean sample weight of a function (default 0.01, 0..1)"},
      {"certificate-rounds", "N", "genus > 0: certificate rounds per attempt of the untangling (0..64, default 16); they stop earlier once every cell is certified or the count stalls, so fewer bound the time on solids whose count still falls (sharp creases) and may leave cells uncertified"},
      {"untangle-start", "rounds|passes", "genus > 0: rounds (default): the certificate rounds alone first, the per-cuboid passes only where they leave cells uncertified (then from the fit, as with passes); passes: the per-cuboid passes, then the certificate rounds"},
      {"measure-lattice", "N", "genus > 0: lattice_negative_fraction at the cell centres of an N^3 lattice per cuboid (default 64, 4..256)"},
      {"centroid-samples", "", "genus > 0: also fit every surface triangle's centroid at its surface-map parameter (default: where a cuboid's surface map is squeezed)"},
      {"vertex-samples", "", "genus > 0: fit the surface vertices only, no centroids, squeezed or not"},
      {"one-cuboid", "", "genus 0: one cuboid even where its surface map is squeezed or its spline folds (default: a squeezed solid, squeeze_rounds > 0 or surface_least_density below --squeezed-below, goes through the GPC with its limbs as caps; a one-cuboid spline with negative_jacobian_fraction > 0 is made over the GPC too and the one folding at fewer Gauss points kept)"},
      {"surface-weight", "W", "genus > 0: least-squares weight of a surface vertex against a grid node (default 1)"},
      {"knot-growth", "G", "genus > 0, --adaptive-knots: each level adds lines until the control points grow by G (default 1.4)"},
  }, "genus > 0: the cuboids' untangling on N threads (default 1); genus 0 runs on one (same output for any N)");
  const Args args = parse_args(argv, specs);
  if (print_help_if_asked(args, "volspline mesh2spline MESH -o OUT.json [options]",
                          "Maps a closed triangle mesh (OBJ, OFF, PLY, STL, glTF/GLB) of a solid to a trivariate\n"
                          "spline (thesis ch. 3 and 4): genus 0 to one cuboid and a T-spline; genus > 0 to a\n"
                          "generalized poly-cube (as volspline gpc) and one spline over all its cuboids (JSON\n"
                          "format volspline-gpc-spline; eval --cuboid K). Exit 2 on bad input (open,\n"
                          "non-manifold, NaN) with a message naming the problem.",
                          specs))
    return 0;
  if (args.positional.size() != 1) throw UsageError("expects exactly one MESH (see --help)");
  const std::string output = args.get("output");
  if (output.empty()) throw UsageError("needs -o OUT.json");

  pipeline::Mesh2SplineOptions options;
  options.max_rms_rel = args.get_double("max-rms", options.max_rms_rel);
  options.max_surface_error_rel = args.get_double("max-surface-error", options.max_surface_error_rel);
  options.area_balance_iterations = args.get_int("area-balance", options.area_balance_iterations);
  options.squeezed_below = args.get_double("squeezed-below", options.squeezed_below);
  options.min_scaled_jacobian = args.get_double("repair-jacobian", options.min_scaled_jacobian);
  options.max_control_points = args.get_int("max-control-points", options.max_control_points);
  options.max_levels = args.get_int("max-levels", options.max_levels);
  options.initial_cells = args.get_int("initial-cells", options.initial_cells);
  if (args.get_int("threads", 1) < 1) throw UsageError("--threads must be >= 1");
  if (args.has("compare-uniform")) options.compare_uniform = pipeline::Mesh2SplineOptions::CompareUniform::On;
  if (args.has("no-untangle")) options.untangle = pipeline::Mesh2SplineOptions::Untangle::Off;
  const std::string fit = args.get("fit", "grid");
  if (fit == "grid")
    options.fit = pipeline::Mesh2SplineFit::Grid;
  else if (fit == "meshless")
    options.fit = pipeline::Mesh2SplineFit::Meshless;
  else
    throw UsageError("--fit must be grid or meshless, got '" + fit + "'");
  const std::string weights = args.get("weights", "meanvalue");
  if (weights == "meanvalue")
    options.weights = param::SurfaceWeights::MeanValue;
  else if (weights == "cotan")
    options.weights = param::SurfaceWeights::Cotan;
  else
    throw UsageError("--weights must be meanvalue or cotan, got '" + weights + "'");
  const std::string& path = args.positional[0];
  OutputFiles files;
  files.input(path);
  if (args.has("corners")) files.input(args.get("corners"));
  files.output("-o", output);
  for (const char* flag : {"vtk", "glb", "gismo", "mfem", "bezier", "stats-json"})
    if (args.has(flag)) files.output(std::string("--") + flag, args.get(flag));
  if (args.has("corners")) options.corners = read_corner_ids(args.get("corners"));

  const int vtk_linear = args.has("vtk-linear") ? args.get_int("vtk-linear", 24) : 0;
  if (args.has("vtk-linear") && (vtk_linear < 1 || vtk_linear > 512))
    throw UsageError("--vtk-linear must be in 1..512, got " + std::to_string(vtk_linear));
  const mesh::TriangleMesh input = io::read_mesh(path);
  const double limbs = args.get_double("limbs", 0.0);
  if (!(limbs >= 0.0 && limbs < 1.0)) throw UsageError("--limbs expects a fraction in [0, 1)");
  if (solid_genus(input, path) > 0 || limbs > 0.0) {
    run_gpc_mesh2spline_command(args, input, path, options, vtk_linear, files);
    return 0;
  }
  if (!args.has("one-cuboid")) options.squeezed = pipeline::Mesh2SplineOptions::Squeezed::Refuse;
  std::optional<pipeline::Mesh2SplineResult> run;
  try {
    ProgressBar bar(!args.has("quiet"));
    run = pipeline::run_mesh2spline(input, path, options, bar.progress());
    bar.finish();
  } catch (const pipeline::SqueezedOneCuboid& e) {
    if (!args.has("quiet"))
      std::fprintf(stderr, "mesh2spline: %s; going through the GPC with its limbs as caps (--one-cuboid keeps one cuboid)\n",
                   e.what());
    run_gpc_mesh2spline_command(args, input, path, options, vtk_linear, files);
    return 0;
  }
  const pipeline::Mesh2SplineResult& result = *run;
  if (!args.has("one-cuboid") && pipeline::one_cuboid_folds(options, result.stats)) {
    if (!args.has("quiet"))
      std::fprintf(stderr,
                   "mesh2spline: the one-cuboid spline folds at %.3g of its Gauss points; going through the GPC with "
                   "its limbs as caps too (--one-cuboid keeps one cuboid)\n",
                   result.stats.negative_jacobian_fraction);
    const pipeline::GpcMesh2SplineOptions gpc = gpc_options(args, options);
    std::optional<pipeline::GpcMesh2SplineResult> over_gpc;
    try {
      over_gpc = run_gpc_job(args, input, path, gpc);
    } catch (const polycube::DecompositionError& e) {
      if (!args.has("quiet")) std::fprintf(stderr, "mesh2spline: no GPC (%s); keeping one cuboid\n", e.what());
    }
    if (over_gpc && pipeline::gpc_folds_less(over_gpc->stats, result.stats)) {
      write_gpc_outputs(args, path, gpc, *over_gpc, vtk_linear, files);
      return 0;
    }
    if (over_gpc && !args.has("quiet"))
      std::fprintf(stderr, "mesh2spline: the GPC spline folds at %.3g of its Gauss points; keeping one cuboid\n",
                   over_gpc->stats.negative_jacobian_fraction);
  }

  files.stage(output, io::serialize_spline_json(result.spline));
  if (args.has("vtk")) {
    if (vtk_linear > 0) {
      files.stage(args.get("vtk"), io::serialize_spline_vtu(result.spline, {vtk_linear, vtk_linear, vtk_linear}));
    } else {
      files.stage(args.get("vtk"), io::serialize_bezier_vtu(result.spline));
    }
  }
  if (args.has("glb")) files.stage(args.get("glb"), io::serialize_spline_glb(result.spline));
  if (args.has("gismo") || args.has("mfem")) {
    const spline::BsplineMultipatch patches = spline::multipatch_from_tspline(result.spline);
    if (args.has("gismo")) files.stage(args.get("gismo"), io::serialize_gismo_xml(patches));
    if (args.has("mfem")) files.stage(args.get("mfem"), io::serialize_mfem_mesh(patches));
  }
  if (args.has("bezier")) files.stage(args.get("bezier"), io::serialize_bezier_extraction_json(result.spline));
  const pipeline::Mesh2SplineStats& s = result.stats;
  if (args.has("stats-json")) {
    nlohmann::ordered_json j = fit_stats_json(s, path, fit);
    add_certificate_json(j, s);
    j["min_scaled_jacobian"] = s.min_scaled_jacobian;
    j["negative_jacobian_fraction"] = s.negative_jacobian_fraction;
    j["jacobian_samples"] = s.jacobian_samples;
    j["semi_standard_max_error"] = s.semi_standard_max_error;
    j["cuboids"] = s.cuboids;
    j["flipped_triangles"] = s.flipped_triangles;
    j["squeeze_rounds"] = s.squeeze_rounds;
    j["surface_least_density"] = std::isfinite(s.surface_least_density) ? nlohmann::ordered_json(s.surface_least_density) : nlohmann::ordered_json(nullptr);
    j["negative_jacobian_fraction_fit"] = s.negative_jacobian_fraction_fit;
    j["repaired_control_points"] = s.repaired_control_points;
    j["untangled_control_points"] = s.untangled_control_points;
    j["creased_control_points"] = s.creased_control_points;
    j["grid_inverted_hexes"] = s.grid_inverted_hexes;
    j["grid_min_scaled_jacobian"] = s.grid_min_scaled_jacobian;
    j["samples"] = s.samples;
    j["min_corner_distance_rel"] = s.min_corner_distance_rel;
    j["corners"] = s.corners;
    if (options.compare_uniform == pipeline::Mesh2SplineOptions::CompareUniform::On) {
      j["uniform_control_points"] = s.uniform_control_points >= 0 ? nlohmann::ordered_json(s.uniform_control_points)
                                                                   : nlohmann::ordered_json(nullptr);
      j["uniform_rms_rel"] = s.uniform_rms_rel;
    }
    j["times_s"] = stage_times_json(s.times_s);
    files.stage(args.get("stats-json"), j.dump(2) + "\n");
  }
  files.commit();
  if (!args.has("quiet"))
    std::fprintf(stderr,
                 "mesh2spline: %d control points, %d levels, rms_rel %.3g, hausdorff_rel %.3g, "
                 "certified fold-free cells %.4g %% (%zu not), min scaled Jacobian %.3g at the Gauss points\n",
                 s.control_points, s.levels, s.rms_rel, s.hausdorff_rel, 100.0 * s.jacobian_certified_fraction,
                 s.uncertified_cells.size(), s.min_scaled_jacobian);
  return 0;
}

}  // namespace volspline::cli
