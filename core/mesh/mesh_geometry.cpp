// SPDX-License-Identifier: MIT
#include "core/mesh/mesh_geometry.h"

#include <Eigen/Geometry>

namespace volspline::mesh {
namespace {

/// Cross product of two edges of f: twice the area times the unit normal.
Eigen::Vector3d face_cross(const HalfedgeMesh& mesh, int f) {
  const auto c = mesh.face_vertices(f);
  const Eigen::Vector3d a = mesh.vertex_position(c[0]);
  return (mesh.vertex_position(c[1]) - a).cross(mesh.vertex_position(c[2]) - a);
}

}  // namespace

std::vector<double> face_areas(const HalfedgeMesh& mesh) {
  std::vector<double> areas(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) areas[f] = 0.5 * face_cross(mesh, f).norm();
  return areas;
}

Positions face_normals(const HalfedgeMesh& mesh) {
  Positions normals = Positions::Zero(mesh.num_faces(), 3);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d n = face_cross(mesh, f);
    const double length = n.norm();
    if (length > 0.0) normals.row(f) = (n / length).transpose();
  }
  return normals;
}

Positions vertex_normals(const HalfedgeMesh& mesh) {
  Positions normals = Positions::Zero(mesh.num_vertices(), 3);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::RowVector3d n = face_cross(mesh, f).transpose();
    for (int v : mesh.face_vertices(f)) normals.row(v) += n;
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double length = normals.row(v).norm();
    if (length > 0.0) normals.row(v) /= length;
  }
  return normals;
}

std::vector<double> edge_lengths(const HalfedgeMesh& mesh) {
  std::vector<double> lengths(mesh.num_edges());
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto ends = mesh.edge_vertices(e);
    lengths[e] = (mesh.vertex_position(ends[1]) - mesh.vertex_position(ends[0])).norm();
  }
  return lengths;
}

}  // namespace volspline::mesh
