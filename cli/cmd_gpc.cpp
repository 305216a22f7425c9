// SPDX-License-Identifier: MIT
#include <cstdio>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/corners_file.h"
#include "cli/output_files.h"
#include "cli/progress_bar.h"
#include "core/io/file_bytes.h"
#include "core/io/gpc_json.h"
#include "core/io/gpc_writers.h"
#include "core/io/mesh_io.h"
#include "core/pipeline/gpc_job.h"
#include "core/pipeline/gpc_outputs.h"

namespace volspline::cli {

int run_gpc(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = with_job_options({
      {"output", "DOMAIN.json", "GPC domain (cuboids, glued faces, transition maps, ill-points) to write (required; also -o)"},
      {"glb", "SEG.glb", "the surface coloured by cuboid with poly-edges and corners"},
      {"vtk", "GRID.vtu", "the hex mesh: every cuboid's grid over shared nodes and the padding layer, cell data cuboid, scaled_jacobian, padding"},
      {"corners", "FILE", "8 corner vertex ids of a genus-0 solid's cuboid (cube corner c at (c&1, c>>1&1, c>>2&1))"},
      {"grid-nodes", "N", "about N volumetric grid nodes over all cuboids (default 24000)"},
      {"area-balance", "N", "stretch-reweighting rounds of every cuboid's surface map (default 4, 0 = the plain Tutte/Floater map)"},
      {"squeezed-below", "D", "widen every cuboid's surface map where a vertex's linear parameter density is below D (default 0 = off; mesh2spline: 0.1)"},
      {"no-untangle", "", "keep the harmonic grid's folds (the thesis's plain Eq. 3.1 map)"},
      {"no-padding", "", "the hex mesh without the padding layer under the surface (the cuboid grids alone)"},
      {"no-face-sliding", "", "keep the folds that the padded hex mesh's untangling with the surface held leaves, and its surface nodes where the surface maps put them up to the last stage (default: untangle again with the nodes inside each exposed cube face sliding on it; mesh2spline: off)"},
      {"quality-sweeps", "N", "sweeps of the last stage, which raises the hex mesh's least scaled Jacobian with every surface node sliding on the surface (default 300; 0 = off)"},
      {"padded-reference", "mean|own|better", "reference cell of the padded hex mesh's untanglers: one cube of the mean hex volume, each hex's own, or both and the one leaving fewer folds (default better)"},
      {"no-merge", "", "keep every T-shape arm, tube and cap its own cuboid (no merging across cuts)"},
      {"level-set-cuts", "", "cut on the Morse function's level sets (default: move each cut to the shortest loop separating the same boundaries)"},
      {"limbs", "P", "limb ends become caps when their branch is at least P of the shape's graph diameter long (default 0.15; 0 = off; a genus-0 blob has no limb and stays one cuboid)"},
  }, "accepted for scripts; the job runs on one thread (same output for any N)");
  const Args args = parse_args(argv, specs);
  if (print_help_if_asked(args, "volspline gpc MESH -o DOMAIN.json [options]",
                          "Builds the generalized poly-cube (GPC) domain of a closed solid of any genus (thesis\n"
                          "ch. 3): decomposition into caps, tubes and T-shapes along cuts that bound discs inside\n"
                          "the solid, cuboids with glued faces and their transition maps, per-cuboid surface maps\n"
                          "and volumetric grids with the glued nodes shared. Exit 2 on bad input (open,\n"
                          "non-manifold, several components, degenerate), 1 if the construction fails.",
                          specs))
    return 0;
  if (args.positional.size() != 1) throw UsageError("expects exactly one MESH (see --help)");
  const std::string output = args.get("output");
  if (output.empty()) throw UsageError("needs -o DOMAIN.json");
  pipeline::GpcOptions options;
  options.threads = args.get_int("threads", options.threads);
  options.grid.target_nodes = args.get_int("grid-nodes", options.grid.target_nodes);
  options.grid.area_balance_iterations = args.get_int("area-balance", options.grid.area_balance_iterations);
  options.grid.squeezed_below = args.get_double("squeezed-below", options.grid.squeezed_below);
  if (args.has("no-untangle")) options.grid.untangle = param::GpcGridOptions::Untangle::Off;
  if (args.has("no-padding")) options.grid.padding = param::GpcGridOptions::Padding::Off;
  if (args.has("no-face-sliding")) options.grid.face_sliding = param::GpcGridOptions::FaceSliding::Off;
  options.grid.min_quality_sweeps = args.get_int("quality-sweeps", options.grid.min_quality_sweeps);
  if (args.has("padded-reference")) {
    const std::string r = args.get("padded-reference");
    if (r == "mean") options.grid.padded_reference = param::GpcGridOptions::PaddedReference::MeanCell;
    else if (r == "own") options.grid.padded_reference = param::GpcGridOptions::PaddedReference::OwnCell;
    else if (r == "better") options.grid.padded_reference = param::GpcGridOptions::PaddedReference::Better;
    else throw UsageError("--padded-reference expects mean, own or better");
  }
  if (args.has("no-merge")) options.merge_cuboids = false;
  if (args.has("level-set-cuts")) options.cuts = polycube::CutPlacement::LevelSet;
  if (args.has("limbs")) {
    options.limb_persistence = args.get_double("limbs", 0.0);
    if (!(options.limb_persistence >= 0.0 && options.limb_persistence < 1.0))
      throw UsageError("--limbs expects a fraction in [0, 1)");
  }
  const std::string& path = args.positional[0];
  OutputFiles files;
  files.input(path);
  if (args.has("corners")) files.input(args.get("corners"));
  files.output("-o", output);
  for (const char* flag : {"vtk", "glb", "stats-json"})
    if (args.has(flag)) files.output(std::string("--") + flag, args.get(flag));
  if (args.has("corners")) options.corners = read_corner_ids(args.get("corners"));

  // The bar starts before the read: a large mesh takes a second to parse.
  ProgressBar bar(!args.has("quiet"));
  bar.progress().report("read", 0.0);
  const mesh::TriangleMesh input = io::read_mesh(path);
  const pipeline::GpcResult result = pipeline::run_gpc(input, path, options, bar.progress());
  bar.finish();

  files.stage(output, io::serialize_gpc_domain(result.construction.domain));
  if (args.has("vtk")) {
    const param::HexMesh& m = result.map.hex_mesh;
    files.stage(args.get("vtk"), io::serialize_hex_mesh_vtu({&m.xyz, &m.hexes, &m.hex_group, &m.padding}));
  }
  if (args.has("glb")) files.stage(args.get("glb"), pipeline::gpc_segmentation_glb(result));
  if (args.has("stats-json")) files.stage(args.get("stats-json"), pipeline::gpc_stats_json(result.stats, path));
  files.commit();
  const pipeline::GpcStats& s = result.stats;
  if (!args.has("quiet"))
    std::fprintf(stderr,
                 "gpc: genus %d, %d T-shapes, %d tubes, %d caps -> %d cuboids, %d ill-points; %d inverted hexes, "
                 "min scaled Jacobian %.3g\n",
                 s.genus, s.t_shapes, s.tubes, s.caps, s.cuboids, s.ill_points, s.grid_inverted_hexes,
                 s.grid_min_scaled_jacobian);
  return 0;
}

}  // namespace volspline::cli
