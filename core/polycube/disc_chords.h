// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::polycube {

/// What cut_disc_chords did to the mesh.
struct DiscChords {
  /// Per chord: its vertex path in the refined mesh, from its first end to its second.
  std::vector<std::vector<int>> paths;
  /// Per face of the refined mesh: the input face it lies in (a split face keeps its id for one
  /// part; the other parts are appended).
  std::vector<int> face_origin;
  /// Per added vertex (ids num_vertices() of the input + k, ascending): the refined-mesh edge
  /// (a, b) it was put on, both ids smaller than its own, and t with x = (1 − t)·x_a + t·x_b.
  std::vector<std::array<int, 2>> new_vertex_edge;
  std::vector<double> new_vertex_t;
};

/// Straight cuts across a disc of a surface (the inner edges of a T-shape's centre cuboid,
/// §3.3.2 Algorithm 3 / Fig. 3.7). Shortest edge paths between boundary points of a disc pinch
/// against each other and the boundary on coarse meshes; here the disc (faces `region` of `mesh`,
/// boundary passing through `corners`) is mapped by Floater's mean-value map onto a convex
/// polygon inscribed in the unit circle, one side per boundary arc between consecutive corners
/// (corner angles proportional to arc length, bijective by Floater's theorem, checked: every face
/// keeps its orientation), and every chord, a straight segment between two boundary vertices, is
/// inserted as an edge path by split_at_level of its line's signed distance (the boundary and
/// earlier chords frozen). A chord of a convex polygon meets the boundary only at its ends, and
/// two chords with non-interleaved ends meet at most at a shared end, so the paths are disjoint
/// by construction; two crossing chords share one vertex, at their crossing. The mesh is refined in place: positions of added vertices interpolated along
/// the edge they split; faces outside the region and all boundary edges of the region unchanged.
/// Returns false with the reason in *why (region not a disc, corner not on its boundary, a chord
/// end not on the boundary, a folded map).
bool cut_disc_chords(mesh::TriangleMesh& mesh, const std::vector<int>& region, const std::vector<int>& corners,
                     const std::vector<std::array<int, 2>>& chords, DiscChords& out, std::string* why);

/// Extends per-vertex data over the vertices cut_disc_chords added (linear along their edges).
void interpolate_added_vertices(const DiscChords& chords, std::vector<double>& data);

}  // namespace volspline::polycube
