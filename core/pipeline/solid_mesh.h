// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/common/progress.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/mesh_report.h"

namespace volspline::pipeline {

/// A validated closed surface of a solid with outward normals, and its report.
struct SolidMesh {
  mesh::HalfedgeMesh mesh;
  mesh::MeshReport report;
};

/// Checks that `input` bounds a solid: closed, one component, consistently oriented, no
/// degenerate face; flips it when all normals point inwards. Any genus.
/// progress: "validate" with the fraction done after each step (half-edge build, analysis, flip).
/// Throws volspline::Error naming `name`, `job` and the first problem (exit code 2);
/// volspline::Cancelled if progress asks to stop.
SolidMesh validate_solid_mesh(const mesh::TriangleMesh& input, const std::string& name, const std::string& job,
                              const Progress& progress = {});

}  // namespace volspline::pipeline
