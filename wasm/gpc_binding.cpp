// SPDX-License-Identifier: MIT
#include "wasm/gpc_binding.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/common/error.h"
#include "core/io/gpc_json.h"
#include "core/io/gpc_writers.h"
#include "core/io/mesh_io.h"
#include "core/pipeline/gpc_job.h"
#include "core/pipeline/gpc_outputs.h"
#include "core/polycube/solid_decomposition.h"
#include "wasm/guarded.h"
#include "wasm/js_values.h"

namespace volspline::wasm {

using emscripten::val;

namespace {

pipeline::GpcOptions job_options_from_js(const val& o) {
  pipeline::GpcOptions options;
  // Wide integer ranges here; run_gpc checks the real ones and names the field.
  options.grid.target_nodes = integer_option(o, "grid_nodes", options.grid.target_nodes, -2000000000, 2000000000);
  options.grid.untangle = bool_option(o, "untangle", true) ? param::GpcGridOptions::Untangle::On
                                                            : param::GpcGridOptions::Untangle::Off;
  options.snap = number_option(o, "snap", options.snap);
  options.merge_cuboids = bool_option(o, "merge_cuboids", options.merge_cuboids);
  if (bool_option(o, "level_set_cuts", false)) options.cuts = polycube::CutPlacement::LevelSet;
  options.limb_persistence = number_option(o, "limb_persistence", options.limb_persistence);
  if (!(options.limb_persistence < 1.0))
    throw Error("option 'limb_persistence': expected a fraction in [0, 1) of the graph diameter, or negative (automatic)");
  options.threads = integer_option(o, "threads", options.threads, 1, 1024);
  options.corners = corner_ids_option(o);
  return options;
}

val bytes_to_js(const std::string& bytes) {
  return uint8_array(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

val float_list(const float* v) {
  val out = val::array();
  for (int k = 0; k < 3; ++k) out.call<void>("push", double(v[k]));
  return out;
}

// One point per face corner, so that every triangle takes its cuboid's colour with sharp borders
// (as in the segmented GLB).
val surface_to_js(const pipeline::GpcResult& r, float* lo, float* hi) {
  const mesh::TriangleMesh& s = r.surface;
  std::vector<float> xyz, colour;
  std::vector<std::uint32_t> face_cuboid;
  xyz.reserve(9 * s.num_faces());
  colour.reserve(9 * s.num_faces());
  for (int t = 0; t < s.num_faces(); ++t) {
    const int cuboid = std::max(r.face_cuboid[t], 0);
    const auto c = io::segment_colour(cuboid);
    face_cuboid.push_back(static_cast<std::uint32_t>(cuboid));
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) {
        const float x = static_cast<float>(s.positions(s.triangles(t, k), d));
        xyz.push_back(x);
        colour.push_back(c[d]);
        lo[d] = std::min(lo[d], x);
        hi[d] = std::max(hi[d], x);
      }
  }
  val out = val::object();
  out.set("positions", float32_array(xyz.data(), xyz.size()));
  out.set("colours", float32_array(colour.data(), colour.size()));
  out.set("face_cuboid", uint32_array(face_cuboid.data(), face_cuboid.size()));
  return out;
}

}  // namespace

val gpc(const val& bytes, const std::string& name, const val& options, const val& progress) {
  return guarded([&] {
    const pipeline::GpcOptions job = job_options_from_js(options);
    const bool outputs = bool_option(options, "outputs", true);
    const mesh::TriangleMesh input =
        io::parse_mesh(bytes_from_js(bytes, "mesh '" + name + "'"), io::mesh_format_from_path(name), name);
    pipeline::GpcResult result;
    try {
      result = pipeline::run_gpc(input, name, job, progress_from_js(progress));
    } catch (const polycube::DecompositionError& e) {
      // The CLI's exit 1: the input was fine, the construction was not.
      return failure(std::string("gpc failed: ") + e.what());
    }

    val out = val::object();
    out.set("ok", true);
    out.set("stats", val::global("JSON").call<val>("parse", pipeline::gpc_stats_json(result.stats, name)));
    float lo[3], hi[3];
    std::fill(lo, lo + 3, std::numeric_limits<float>::max());
    std::fill(hi, hi + 3, -std::numeric_limits<float>::max());
    out.set("surface", surface_to_js(result, lo, hi));
    const pipeline::GpcSegmentation seg = pipeline::gpc_segmentation(result);
    std::vector<float> lines, corners;
    for (const auto& line : seg.poly_edges)
      for (std::size_t i = 0; i + 1 < line.size(); ++i)
        for (int e = 0; e < 2; ++e)
          for (int d = 0; d < 3; ++d) lines.push_back(static_cast<float>(line[i + e](d)));
    for (const Eigen::Vector3d& p : seg.corners)
      for (int d = 0; d < 3; ++d) corners.push_back(static_cast<float>(p(d)));
    out.set("poly_edges", float32_array(lines.data(), lines.size()));
    out.set("corners", float32_array(corners.data(), corners.size()));
    out.set("bbox_min", float_list(lo));
    out.set("bbox_max", float_list(hi));
    if (outputs) {
      out.set("domain_json", bytes_to_js(io::serialize_gpc_domain(result.construction.domain)));
      out.set("glb", bytes_to_js(pipeline::gpc_segmentation_glb(result)));
    }
    return out;
  });
}

}  // namespace volspline::wasm
