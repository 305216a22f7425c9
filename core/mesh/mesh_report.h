// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>

#include "core/mesh/halfedge_mesh.h"

namespace volspline::mesh {

/// Topological and geometric facts about a mesh (what `volspline info` prints).
struct MeshReport {
  int num_vertices = 0;               ///< all vertices, referenced or not
  int num_unreferenced_vertices = 0;  ///< vertices used by no face (kept, but not part of χ)
  int num_faces = 0;
  int num_edges = 0;
  int num_boundary_edges = 0;
  bool closed = false;          ///< no boundary edge
  bool manifold = false;        ///< edge- and vertex-manifold (always true once built)
  int num_boundary_loops = 0;
  int num_components = 0;       ///< edge-connected components of faces
  bool consistently_oriented = false;  ///< build() did not have to flip any face
  int num_flipped_faces = 0;           ///< faces build() reversed to make orientation consistent
  int num_degenerate_faces = 0;  ///< zero area (relative to bbox diagonal squared, 1e-14)
  int first_degenerate_face = -1;  ///< lowest degenerate face id, -1 if none
  int euler_characteristic = 0;  ///< V - E + F, V counting referenced vertices only
  int genus = -1;                ///< (2 - χ - b) / 2 for one connected component; -1 otherwise
  double signed_volume = 0.0;    ///< divergence theorem, model units³; > 0: outward normals (closed)
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero();  ///< over all vertices, model units
  Eigen::Vector3d bbox_max = Eigen::Vector3d::Zero();
};

/// Computes the report of a built half-edge mesh in O(V + F). Never throws.
MeshReport analyze_mesh(const HalfedgeMesh& mesh);

}  // namespace volspline::mesh
