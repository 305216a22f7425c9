// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "core/mesh/halfedge_mesh.h"

namespace volspline::mesh {

/// Topological and geometric facts about a mesh (what `volspline info` prints).
struct MeshReport {
  int num_vertices = 0;
  int num_faces = 0;
  int num_edges = 0;
  bool closed = false;          ///< no boundary edge
  bool manifold = false;        ///< edge- and vertex-manifold (always true once built)
  int num_boundary_loops = 0;
  int num_components = 0;       ///< edge-connected components of faces
  bool consistently_oriented = false;
  int num_degenerate_faces = 0;  ///< zero area (relative to bbox diagonal squared, 1e-14)
  int euler_characteristic = 0;  ///< V - E + F
  int genus = -1;                ///< (2 - χ - b) / 2 for one connected component; -1 otherwise
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d bbox_max = Eigen::Vector3d::Zero();
};

/// Computes the report of a built half-edge mesh.
MeshReport analyze_mesh(const HalfedgeMesh& mesh);

}  // namespace volspline::mesh
