// SPDX-License-Identifier: MIT
#include "core/pipeline/solid_mesh.h"

#include "core/common/error.h"

namespace volspline::pipeline {

SolidMesh validate_solid_mesh(const mesh::TriangleMesh& input, const std::string& name, const std::string& job,
                              const Progress& progress) {
  progress.report("validate", 0.0);
  mesh::HalfedgeMesh hm = mesh::HalfedgeMesh::build(input, name);
  progress.report("validate", 0.5);
  mesh::MeshReport r = mesh::analyze_mesh(hm);
  progress.report("validate", 0.8);
  const std::string prefix = "mesh '" + name + "': ";
  if (!r.closed)
    throw Error(prefix + "not closed (" + std::to_string(r.num_boundary_edges) + " boundary edges); " + job +
                " needs the closed surface of a solid");
  if (r.num_components != 1)
    throw Error(prefix + std::to_string(r.num_components) + " connected components; " + job + " needs exactly one");
  if (!r.consistently_oriented)
    throw Error(prefix + "inconsistently oriented faces (" + std::to_string(r.num_flipped_faces) +
                " would have to be flipped)");
  if (r.num_degenerate_faces > 0)
    throw Error(prefix + std::to_string(r.num_degenerate_faces) + " degenerate (zero-area) faces, first: face " +
                std::to_string(r.first_degenerate_face));
  if (r.signed_volume < 0.0) {
    // Consistently inward-facing: flip every face so normals point outwards.
    mesh::TriangleMesh flipped = hm.to_triangle_mesh();
    flipped.triangles.col(1).swap(flipped.triangles.col(2));
    hm = mesh::HalfedgeMesh::build(flipped, name);
    r = mesh::analyze_mesh(hm);
  }
  progress.report("validate", 1.0);
  return SolidMesh{std::move(hm), r};
}

}  // namespace volspline::pipeline
