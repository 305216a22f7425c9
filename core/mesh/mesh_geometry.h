// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/mesh/halfedge_mesh.h"

namespace volspline::mesh {

/// Area of every face, model units², length num_faces().
std::vector<double> face_areas(const HalfedgeMesh& mesh);

/// Unit normal of every face (right-hand rule on the stored corner order), num_faces()×3;
/// a zero row for a face of zero area.
Positions face_normals(const HalfedgeMesh& mesh);

/// Unit normal of every vertex, num_vertices()×3: the area-weighted mean of the incident face
/// normals (sum of unnormalized face cross products). A zero row for an unreferenced vertex or
/// one whose weighted sum vanishes.
Positions vertex_normals(const HalfedgeMesh& mesh);

/// Euclidean length of every edge, model units, length num_edges().
std::vector<double> edge_lengths(const HalfedgeMesh& mesh);

}  // namespace volspline::mesh
