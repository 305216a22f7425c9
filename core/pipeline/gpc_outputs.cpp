// SPDX-License-Identifier: MIT
#include "core/pipeline/gpc_outputs.h"

#include <nlohmann/json.hpp>

#include "core/io/gpc_writers.h"

namespace volspline::pipeline {

GpcSegmentation gpc_segmentation(const GpcResult& result) {
  GpcSegmentation out;
  for (const polycube::CuboidSurface& s : result.construction.surfaces) {
    for (const std::vector<int>& path : s.layout.poly_edges) {
      std::vector<Eigen::Vector3d> line;
      line.reserve(path.size());
      for (int v : path) line.push_back(s.mesh.positions.row(v).transpose());
      out.poly_edges.push_back(std::move(line));
    }
    for (int c : s.layout.corners) out.corners.push_back(s.mesh.positions.row(c).transpose());
  }
  return out;
}

std::string gpc_segmentation_glb(const GpcResult& result) {
  const GpcSegmentation s = gpc_segmentation(result);
  return io::serialize_segmented_glb(result.surface, result.face_cuboid, s.poly_edges, s.corners);
}

std::string gpc_stats_json(const GpcStats& s, const std::string& input) {
  nlohmann::ordered_json j;
  j["input"] = input;
  j["genus"] = s.genus;
  j["t_shapes"] = s.t_shapes;
  j["tubes"] = s.tubes;
  j["caps"] = s.caps;
  j["cuboids"] = s.cuboids;
  j["interfaces"] = s.interfaces;
  j["ill_points"] = s.ill_points;
  j["flipped_triangles"] = s.flipped_triangles;
  j["grid_inverted_hexes"] = s.grid_inverted_hexes;
  j["grid_harmonic_inverted_hexes"] = s.grid_harmonic_inverted_hexes;
  j["grid_min_scaled_jacobian"] = s.grid_min_scaled_jacobian;
  j["cuboid_grid_inverted_hexes"] = s.cuboid_grid_inverted_hexes;
  j["cuboid_grid_min_scaled_jacobian"] = s.cuboid_grid_min_scaled_jacobian;
  j["padding_hexes"] = s.padding_hexes;
  j["interface_gap_rel"] = s.interface_gap_rel;
  j["face_area_ratio_min"] = s.face_area_ratio_min;
  j["face_area_ratio_max"] = s.face_area_ratio_max;
  j["grid_nodes"] = s.grid_nodes;
  j["shared_nodes"] = s.shared_nodes;
  j["cut_disc_intersections"] = s.cut_disc_intersections;
  j["cut_discs_outside"] = s.cut_discs_outside;
  j["tightened_cuts"] = s.tightened_cuts;
  j["flipped_cuts"] = s.flipped_cuts;
  j["cut_length_rel"] = s.cut_length_rel;
  if (!s.cut_disc_problem.empty()) {
    j["cut_disc_problem"] = s.cut_disc_problem;
    j["cut_disc_crossings"] = s.cut_disc_crossings;
  }
  j["saddles"] = s.num_saddles;
  j["limb_caps"] = s.limb_caps;
  j["limb_persistence"] = s.limb_persistence;
  for (const auto& [name, text] : s.retries()) j[name] = text;
  j["surface_vertices"] = s.surface_vertices;
  nlohmann::ordered_json times = nlohmann::ordered_json::object();
  for (const auto& [stage, seconds] : s.times_s) times[stage] = seconds;
  j["times_s"] = times;
  return j.dump(2) + "\n";
}

}  // namespace volspline::pipeline
