// SPDX-License-Identifier: MIT
#include "core/mesh/edge_weights.h"

#include <Eigen/Geometry>
#include <cassert>

namespace volspline::mesh {

std::vector<double> cotan_weights(const HalfedgeMesh& mesh) {
  // §2.2.1, w_ij = cot γ_ij + cot γ_ji, halved so that L is the standard cotan Laplacian.
  std::vector<double> weights(mesh.num_edges(), 0.0);
  for (int h = 0; h < 3 * mesh.num_faces(); ++h) {
    // The angle opposite h sits at the tip of next(h).
    const Eigen::Vector3d c = mesh.vertex_position(mesh.halfedge_vertex(mesh.halfedge_next(h)));
    const Eigen::Vector3d a = mesh.vertex_position(mesh.halfedge_source(h)) - c;
    const Eigen::Vector3d b = mesh.vertex_position(mesh.halfedge_vertex(h)) - c;
    const double sine = a.cross(b).norm();
    if (sine > 0.0) weights[mesh.halfedge_edge(h)] += 0.5 * a.dot(b) / sine;
  }
  return weights;
}

std::vector<double> mean_value_weights(const HalfedgeMesh& mesh) {
  // §2.2.1, w_ij = (tan(α_ij/2) + tan(β_ji/2)) / r_ij (Floater's mean value coordinates).
  std::vector<double> weights(mesh.num_halfedges(), 0.0);
  // tan(θ/2) = |a × b| / (|a||b| + a·b), stable for all θ in [0, π).
  auto half_tangent = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const double denominator = a.norm() * b.norm() + a.dot(b);
    return denominator > 0.0 ? a.cross(b).norm() / denominator : 0.0;
  };
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    const Eigen::Vector3d xi = mesh.vertex_position(mesh.halfedge_source(h));
    const Eigen::Vector3d to_j = mesh.vertex_position(mesh.halfedge_vertex(h)) - xi;
    const double length = to_j.norm();
    if (length == 0.0) continue;
    double sum = 0.0;
    if (!mesh.halfedge_is_boundary(h)) {
      const int k = mesh.halfedge_vertex(mesh.halfedge_next(h));
      sum += half_tangent(to_j, mesh.vertex_position(k) - xi);
    }
    const int t = mesh.halfedge_twin(h);
    if (!mesh.halfedge_is_boundary(t)) {
      const int k = mesh.halfedge_vertex(mesh.halfedge_next(t));
      sum += half_tangent(to_j, mesh.vertex_position(k) - xi);
    }
    weights[h] = sum / length;
  }
  return weights;
}

std::vector<double> edge_to_halfedge_weights(const HalfedgeMesh& mesh,
                                             const std::vector<double>& edge_weights) {
  assert(static_cast<int>(edge_weights.size()) == mesh.num_edges());
  std::vector<double> weights(mesh.num_halfedges());
  for (int h = 0; h < mesh.num_halfedges(); ++h) weights[h] = edge_weights[mesh.halfedge_edge(h)];
  return weights;
}

}  // namespace volspline::mesh
