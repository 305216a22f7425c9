// SPDX-License-Identifier: MIT
#include "core/mesh/mesh_report.h"

#include <Eigen/Geometry>
#include <vector>

namespace volspline::mesh {

MeshReport analyze_mesh(const HalfedgeMesh& mesh) {
  MeshReport report;
  const int n = mesh.num_vertices();
  const int m = mesh.num_faces();
  report.num_vertices = n;
  report.num_unreferenced_vertices = mesh.num_unreferenced_vertices();
  report.num_faces = m;
  report.num_edges = mesh.num_edges();
  report.num_boundary_edges = mesh.num_boundary_halfedges();
  report.closed = report.num_boundary_edges == 0;
  report.manifold = true;
  report.consistently_oriented = mesh.consistently_oriented();
  report.num_flipped_faces = mesh.num_flipped_faces();

  const int first_boundary = 3 * m;
  std::vector<char> on_loop(mesh.num_halfedges() - first_boundary, 0);
  for (int b = first_boundary; b < mesh.num_halfedges(); ++b) {
    if (on_loop[b - first_boundary]) continue;
    ++report.num_boundary_loops;
    for (int h = b; !on_loop[h - first_boundary]; h = mesh.halfedge_next(h)) {
      on_loop[h - first_boundary] = 1;
    }
  }

  std::vector<int> component(m, -1);
  std::vector<int> pending;
  for (int seed = 0; seed < m; ++seed) {
    if (component[seed] >= 0) continue;
    component[seed] = report.num_components;
    pending.assign(1, seed);
    while (!pending.empty()) {
      const int f = pending.back();
      pending.pop_back();
      for (int g : mesh.face_faces(f)) {
        if (g != no_id && component[g] < 0) {
          component[g] = report.num_components;
          pending.push_back(g);
        }
      }
    }
    ++report.num_components;
  }

  const Positions& x = mesh.positions();
  report.bbox_min = x.colwise().minCoeff().transpose();
  report.bbox_max = x.colwise().maxCoeff().transpose();
  const double diagonal_squared = (report.bbox_max - report.bbox_min).squaredNorm();
  for (int f = 0; f < m; ++f) {
    const auto c = mesh.face_vertices(f);
    const Eigen::Vector3d a = mesh.vertex_position(c[0]);
    const Eigen::Vector3d b = mesh.vertex_position(c[1]);
    const Eigen::Vector3d d = mesh.vertex_position(c[2]);
    const double area = 0.5 * (b - a).cross(d - a).norm();
    if (area <= 1e-14 * diagonal_squared) {
      if (report.num_degenerate_faces == 0) report.first_degenerate_face = f;
      ++report.num_degenerate_faces;
    }
    // Divergence theorem relative to the bbox centre, which keeps cancellation small.
    const Eigen::Vector3d centre = 0.5 * (report.bbox_min + report.bbox_max);
    report.signed_volume += (a - centre).dot((b - centre).cross(d - centre)) / 6.0;
  }

  const int referenced = n - report.num_unreferenced_vertices;
  report.euler_characteristic = referenced - report.num_edges + m;
  if (report.num_components == 1) {
    report.genus = (2 - report.euler_characteristic - report.num_boundary_loops) / 2;
  }
  return report;
}

}  // namespace volspline::mesh
