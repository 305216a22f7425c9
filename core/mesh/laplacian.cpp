// SPDX-License-Identifier: MIT
#include "core/mesh/laplacian.h"

#include <cassert>

#include "core/mesh/edge_weights.h"

namespace volspline::mesh {

std::vector<Triplet> laplacian_triplets(const HalfedgeMesh& mesh,
                                        const std::vector<double>& halfedge_weights) {
  assert(static_cast<int>(halfedge_weights.size()) == mesh.num_halfedges());
  std::vector<Triplet> triplets;
  triplets.reserve(mesh.num_halfedges() + mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.vertex_halfedge(v) == no_id) continue;
    const size_t diagonal = triplets.size();
    triplets.push_back({v, v, 0.0});
    double sum = 0.0;
    for (int h : mesh.vertex_outgoing(v)) {
      triplets.push_back({v, mesh.halfedge_vertex(h), halfedge_weights[h]});
      sum += halfedge_weights[h];
    }
    triplets[diagonal].value = -sum;
  }
  return triplets;
}

std::vector<Triplet> laplacian_triplets(const HalfedgeMesh& mesh, LaplacianWeights weights) {
  switch (weights) {
    case LaplacianWeights::Cotan:
      return laplacian_triplets(mesh, edge_to_halfedge_weights(mesh, cotan_weights(mesh)));
    case LaplacianWeights::MeanValue:
      return laplacian_triplets(mesh, mean_value_weights(mesh));
    case LaplacianWeights::Uniform:
      break;
  }
  return laplacian_triplets(mesh, std::vector<double>(mesh.num_halfedges(), 1.0));
}

}  // namespace volspline::mesh
