// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cassert>
#include <iterator>
#include <string>
#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace volspline::mesh {

/// Id returned where an element does not exist (the face of a boundary halfedge, the halfedge
/// of an unreferenced vertex).
inline constexpr int no_id = -1;

class HalfedgeMesh;

/// What a vertex circulator yields for each outgoing halfedge h of the centre vertex.
enum class CirculatorValue {
  Halfedge,  ///< h itself
  Vertex,    ///< the neighbour at the tip of h
  Face,      ///< the face of h; boundary halfedges (face no_id) are skipped
};

/// Forward range over the one-ring of a vertex; obtain it from HalfedgeMesh::vertex_outgoing,
/// vertex_neighbors or vertex_faces. Valid while the mesh lives. Each step costs O(1); the
/// iterator yields ints (halfedge, vertex or face ids) by value.
template <CirculatorValue kValue>
class VertexRing {
 public:
  class iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = int;
    using difference_type = std::ptrdiff_t;
    using pointer = const int*;
    using reference = int;

    iterator() = default;
    iterator(const HalfedgeMesh* mesh, int start, int halfedge, int turns)
        : mesh_(mesh), start_(start), halfedge_(halfedge), turns_(turns) {
      skip_boundary();
    }
    int operator*() const;
    iterator& operator++() {
      advance();
      skip_boundary();
      return *this;
    }
    iterator operator++(int) {
      iterator old = *this;
      ++*this;
      return old;
    }
    bool operator==(const iterator& other) const {
      return halfedge_ == other.halfedge_ && turns_ == other.turns_;
    }
    bool operator!=(const iterator& other) const { return !(*this == other); }

   private:
    void advance();
    void skip_boundary();

    const HalfedgeMesh* mesh_ = nullptr;
    int start_ = no_id;
    int halfedge_ = no_id;
    int turns_ = 1;  // 0 on the way round, 1 back at start_ (end())
  };

  VertexRing(const HalfedgeMesh* mesh, int start) : mesh_(mesh), start_(start) {}
  iterator begin() const { return iterator(mesh_, start_, start_, start_ == no_id ? 1 : 0); }
  iterator end() const { return iterator(mesh_, start_, start_, 1); }

 private:
  const HalfedgeMesh* mesh_;
  int start_;
};

/// Half-edge connectivity of an edge- and vertex-manifold, orientable triangle mesh, open or
/// closed, with int ids for every element.
///
/// Numbering (stable, deterministic):
/// - face f keeps its input id; its halfedges are 3f, 3f+1, 3f+2, where 3f+k runs from corner
///   k to corner k+1 of the (possibly reoriented, see below) triangle;
/// - boundary halfedges (face no_id) follow the 3F interior ones, one per boundary edge, in edge
///   order; they form closed loops (next/prev walk along the boundary);
/// - edge ids follow the lexicographic order of the sorted vertex pair (min, max).
///
/// Orientation: if some faces are flipped relative to their neighbours but the surface is
/// orientable, build() flips them (per edge-connected component the lowest face id keeps its
/// input orientation), records it in face_is_flipped(), and consistently_oriented() returns
/// false; callers that require orientation (mesh2spline validation) refuse on that flag.
/// A non-orientable surface (Möbius strip, Klein bottle) is rejected.
///
/// One-ring order: outgoing halfedges of v go counter-clockwise seen from the side the faces
/// face (h -> halfedge_twin(halfedge_prev(h))). At a boundary vertex the ring starts with the
/// interior halfedge whose twin is a boundary halfedge and ends with the outgoing boundary
/// halfedge, so neighbours come in order from one boundary neighbour to the other and face i
/// of the ring lies between neighbours i and i+1.
class HalfedgeMesh {
 public:
  /// Builds the connectivity in O(n log n) (in fact linear plus small per-vertex sorts).
  /// `source_name` (a file or upload name) prefixes every error message: "mesh 'x.off': ...".
  /// Unreferenced vertices are allowed (vertex_halfedge() == no_id); see num_unreferenced_vertices.
  /// Throws volspline::Error naming the first offending element on: zero faces; a vertex id out
  /// of range; a face repeating a vertex; a non-finite coordinate; an edge used by more than two
  /// faces; a non-orientable surface; a non-manifold vertex (its faces form several fans).
  static HalfedgeMesh build(const TriangleMesh& mesh, const std::string& source_name = "mesh");

  /// Counts; vertices include unreferenced ones.
  int num_vertices() const { return static_cast<int>(vertex_halfedge_.size()); }
  int num_faces() const { return static_cast<int>(triangles_.rows()); }
  /// Interior plus boundary halfedges: 2 * num_edges().
  int num_halfedges() const { return static_cast<int>(twin_.size()); }
  int num_edges() const { return static_cast<int>(edge_halfedge_.size()); }
  /// Halfedges with no face, = number of boundary edges.
  int num_boundary_halfedges() const { return num_halfedges() - 3 * num_faces(); }
  /// Vertices used by no face.
  int num_unreferenced_vertices() const { return num_unreferenced_vertices_; }

  /// n×3 positions, model units (a copy of the input).
  const Positions& positions() const { return positions_; }
  /// Position of vertex v.
  Eigen::Vector3d vertex_position(int v) const { return positions_.row(v).transpose(); }
  /// m×3 triangles as stored: the input triangles with flipped faces reversed (corners 1 and 2
  /// swapped), so that all faces are consistently oriented.
  const Triangles& triangles() const { return triangles_; }
  /// The input, rebuilt from positions() and triangles().
  TriangleMesh to_triangle_mesh() const { return TriangleMesh{positions_, triangles_}; }
  /// Name used in error messages.
  const std::string& source_name() const { return source_name_; }

  /// True iff no face had to be flipped during build().
  bool consistently_oriented() const { return num_flipped_faces_ == 0; }
  /// Number of faces build() reversed.
  int num_flipped_faces() const { return num_flipped_faces_; }
  /// True iff build() reversed face f to make the orientation consistent.
  bool face_is_flipped(int f) const { return flipped_[f] != 0; }

  /// Next / previous halfedge in the same face, or along the boundary loop for a boundary
  /// halfedge; opposite halfedge of the same edge.
  int halfedge_next(int h) const { return next_[h]; }
  int halfedge_prev(int h) const { return prev_[h]; }
  int halfedge_twin(int h) const { return twin_[h]; }
  /// Tip (target) vertex of h.
  int halfedge_vertex(int h) const { return vertex_[h]; }
  /// Origin vertex of h.
  int halfedge_source(int h) const { return vertex_[twin_[h]]; }
  /// Face of h, no_id for a boundary halfedge.
  int halfedge_face(int h) const { return h < 3 * num_faces() ? h / 3 : no_id; }
  /// Edge of h (shared with its twin).
  int halfedge_edge(int h) const { return edge_[h]; }
  /// True iff h has no face (h >= 3 * num_faces()).
  bool halfedge_is_boundary(int h) const { return h >= 3 * num_faces(); }

  /// First halfedge of the one-ring (outgoing from v, see class comment); no_id if v is
  /// unreferenced.
  int vertex_halfedge(int v) const { return vertex_halfedge_[v]; }
  /// True iff v lies on a boundary loop (false for unreferenced vertices).
  bool vertex_is_boundary(int v) const {
    const int h = vertex_halfedge_[v];
    return h != no_id && halfedge_is_boundary(twin_[h]);
  }
  /// Number of outgoing halfedges (= neighbours) of v.
  int vertex_valence(int v) const;

  /// Halfedge 3f (from corner 0 to corner 1).
  int face_halfedge(int f) const { return 3 * f; }
  /// The three halfedges of f in order: h_k runs from corner k to corner k+1.
  std::array<int, 3> face_halfedges(int f) const { return {3 * f, 3 * f + 1, 3 * f + 2}; }
  /// Corners of f in stored (consistent) order.
  std::array<int, 3> face_vertices(int f) const {
    return {triangles_(f, 0), triangles_(f, 1), triangles_(f, 2)};
  }
  /// Neighbouring face across each halfedge of f (no_id across a boundary edge).
  std::array<int, 3> face_faces(int f) const {
    return {halfedge_face(twin_[3 * f]), halfedge_face(twin_[3 * f + 1]),
            halfedge_face(twin_[3 * f + 2])};
  }

  /// Lower-numbered halfedge of e; always interior (boundary halfedges are numbered last).
  int edge_halfedge(int e) const { return edge_halfedge_[e]; }
  /// Endpoints (origin, tip) of edge_halfedge(e).
  std::array<int, 2> edge_vertices(int e) const {
    const int h = edge_halfedge_[e];
    return {halfedge_source(h), halfedge_vertex(h)};
  }
  /// True iff e has a face on one side only.
  bool edge_is_boundary(int e) const {
    const int h = edge_halfedge_[e];
    return halfedge_is_boundary(h) || halfedge_is_boundary(twin_[h]);
  }

  /// One-ring of v as outgoing halfedges, counter-clockwise (see class comment). Usage:
  /// `for (int h : mesh.vertex_outgoing(v)) ...`. Empty for an unreferenced vertex.
  VertexRing<CirculatorValue::Halfedge> vertex_outgoing(int v) const {
    return {this, vertex_halfedge_[v]};
  }
  /// Neighbour vertices of v in one-ring order.
  VertexRing<CirculatorValue::Vertex> vertex_neighbors(int v) const {
    return {this, vertex_halfedge_[v]};
  }
  /// Faces around v in one-ring order (boundary gap skipped).
  VertexRing<CirculatorValue::Face> vertex_faces(int v) const {
    return {this, vertex_halfedge_[v]};
  }

 private:
  HalfedgeMesh() = default;

  std::string source_name_;
  Positions positions_;
  Triangles triangles_;
  std::vector<int> next_;
  std::vector<int> prev_;
  std::vector<int> twin_;
  std::vector<int> vertex_;
  std::vector<int> edge_;
  std::vector<int> vertex_halfedge_;
  std::vector<int> edge_halfedge_;
  std::vector<char> flipped_;
  int num_flipped_faces_ = 0;
  int num_unreferenced_vertices_ = 0;
};

template <CirculatorValue kValue>
int VertexRing<kValue>::iterator::operator*() const {
  if constexpr (kValue == CirculatorValue::Halfedge) {
    return halfedge_;
  } else if constexpr (kValue == CirculatorValue::Vertex) {
    return mesh_->halfedge_vertex(halfedge_);
  } else {
    return mesh_->halfedge_face(halfedge_);
  }
}

template <CirculatorValue kValue>
void VertexRing<kValue>::iterator::advance() {
  assert(turns_ == 0);
  halfedge_ = mesh_->halfedge_twin(mesh_->halfedge_prev(halfedge_));
  if (halfedge_ == start_) turns_ = 1;
}

template <CirculatorValue kValue>
void VertexRing<kValue>::iterator::skip_boundary() {
  if constexpr (kValue == CirculatorValue::Face) {
    while (turns_ == 0 && mesh_->halfedge_is_boundary(halfedge_)) advance();
  }
}

}  // namespace volspline::mesh
