// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/common/error.h"
#include "core/io/mesh_io.h"
#include "core/io/volume_io.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_report.h"

namespace volspline::cli {

namespace {

// A file whose extension names a volume format (raw, nrrd/nhdr, vtk, mhd/mha, vti, nii/nii.gz).
bool is_volume_path(const std::string& path) {
  try {
    io::volume_format_from_path(path);
    return true;
  } catch (const Error&) {
    return false;
  }
}

// Voxel grid, sample type, spacing, origin, axis directions (world = origin + direction ·
// (index × spacing), Eq. 5.11's X, Y, Z) and the sample range of a volume file.
int print_volume_info(const std::string& path, bool json) {
  const volume::Volume v = io::read_volume(path);
  float lo = v.samples.empty() ? 0.0f : v.samples[0], hi = lo;
  for (float x : v.samples) lo = std::min(lo, x), hi = std::max(hi, x);
  const auto vec = [](const Eigen::Vector3d& a) { return nlohmann::ordered_json{a.x(), a.y(), a.z()}; };
  if (json) {
    nlohmann::ordered_json j;
    j["file"] = path;
    j["dims"] = {v.nx, v.ny, v.nz};
    j["type"] = volume::sample_type_name(v.original_type);
    j["spacing"] = vec(v.spacing);
    j["origin"] = vec(v.origin);
    j["direction"] = {vec(v.direction.col(0)), vec(v.direction.col(1)), vec(v.direction.col(2))};
    j["min"] = lo;
    j["max"] = hi;
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("file                 %s\n", path.c_str());
  std::printf("dims                 %d x %d x %d\n", v.nx, v.ny, v.nz);
  std::printf("type                 %s\n", volume::sample_type_name(v.original_type).c_str());
  std::printf("spacing              %.9g %.9g %.9g\n", v.spacing.x(), v.spacing.y(), v.spacing.z());
  std::printf("origin               %.9g %.9g %.9g\n", v.origin.x(), v.origin.y(), v.origin.z());
  for (int a = 0; a < 3; ++a)
    std::printf("direction %c          %.9g %.9g %.9g\n", "xyz"[a], v.direction(0, a), v.direction(1, a), v.direction(2, a));
  std::printf("values               %.9g .. %.9g\n", lo, hi);
  return 0;
}

}  // namespace

int run_info(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {{"json", "", "print the facts as one JSON object"}};
  const Args args = parse_args(argv, specs);
  if (print_help_if_asked(args, "volspline info FILE [--json]",
                          "Reads a triangle mesh (OBJ, OFF, PLY, STL, glTF/GLB) and prints its vertex and face\n"
                          "counts, whether it is closed and manifold, its components, genus and bounding box.\n"
                          "A non-manifold or broken file is an error (exit 2) naming the first bad element.\n"
                          "A volume (raw, NRRD/NHDR, VTK, MetaImage, VTI, NIfTI) gives its dims, sample type,\n"
                          "spacing, origin, axis directions and value range.",
                          specs))
    return 0;
  if (args.positional.size() != 1) throw UsageError("expects exactly one FILE (see --help)");
  const std::string& path = args.positional[0];
  if (is_volume_path(path)) return print_volume_info(path, args.has("json"));

  const mesh::TriangleMesh triangles = io::read_mesh(path);
  const mesh::HalfedgeMesh halfedges = mesh::HalfedgeMesh::build(triangles, path);
  const mesh::MeshReport r = mesh::analyze_mesh(halfedges);

  if (args.has("json")) {
    nlohmann::ordered_json j;
    j["file"] = path;
    j["vertices"] = r.num_vertices;
    j["faces"] = r.num_faces;
    j["edges"] = r.num_edges;
    j["closed"] = r.closed;
    j["manifold"] = r.manifold;
    j["boundary_loops"] = r.num_boundary_loops;
    j["components"] = r.num_components;
    j["consistently_oriented"] = r.consistently_oriented;
    j["degenerate_faces"] = r.num_degenerate_faces;
    j["unreferenced_vertices"] = r.num_unreferenced_vertices;
    j["flipped_faces"] = r.num_flipped_faces;
    j["euler_characteristic"] = r.euler_characteristic;
    j["genus"] = r.genus >= 0 ? nlohmann::ordered_json(r.genus) : nlohmann::ordered_json(nullptr);
    j["signed_volume"] = r.signed_volume;
    j["bbox_min"] = {r.bbox_min.x(), r.bbox_min.y(), r.bbox_min.z()};
    j["bbox_max"] = {r.bbox_max.x(), r.bbox_max.y(), r.bbox_max.z()};
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("file                 %s\n", path.c_str());
  std::printf("vertices             %d\n", r.num_vertices);
  std::printf("faces                %d\n", r.num_faces);
  std::printf("edges                %d\n", r.num_edges);
  std::printf("closed               %s\n", r.closed ? "yes" : "no");
  std::printf("manifold             %s\n", r.manifold ? "yes" : "no");
  std::printf("boundary loops       %d\n", r.num_boundary_loops);
  std::printf("components           %d\n", r.num_components);
  std::printf("oriented             %s\n", r.consistently_oriented ? "yes" : "no");
  std::printf("degenerate faces     %d\n", r.num_degenerate_faces);
  if (r.num_unreferenced_vertices > 0)
    std::printf("unreferenced verts   %d\n", r.num_unreferenced_vertices);
  if (!r.consistently_oriented)
    std::printf("flipped faces        %d (reoriented to match their neighbours)\n", r.num_flipped_faces);
  std::printf("euler characteristic %d\n", r.euler_characteristic);
  if (r.genus >= 0)
    std::printf("genus                %d\n", r.genus);
  else
    std::printf("genus                undefined (%d components)\n", r.num_components);
  if (r.closed) std::printf("signed volume        %.9g\n", r.signed_volume);
  std::printf("bbox min             %.9g %.9g %.9g\n", r.bbox_min.x(), r.bbox_min.y(), r.bbox_min.z());
  std::printf("bbox max             %.9g %.9g %.9g\n", r.bbox_max.x(), r.bbox_max.y(), r.bbox_max.z());
  return 0;
}

}  // namespace volspline::cli
