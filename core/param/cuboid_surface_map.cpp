// SPDX-License-Identifier: MIT
#include "core/param/cuboid_surface_map.h"

#include <algorithm>
#include <string>

#include "core/common/error.h"
#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/mesh/edge_weights.h"

namespace volspline::param {

Eigen::Vector2d cube_face_coordinates(int face, const Eigen::Vector3d& uvw) {
  const int a = face / 2;
  return Eigen::Vector2d(uvw((a + 1) % 3), uvw((a + 2) % 3));
}

Eigen::Vector3d cube_face_point(int face, double s, double t) {
  const int a = face / 2;
  Eigen::Vector3d uvw;
  uvw(a) = face % 2;
  uvw((a + 1) % 3) = s;
  uvw((a + 2) % 3) = t;
  return uvw;
}

CuboidSurfaceMap compute_cuboid_surface_map(const mesh::HalfedgeMesh& mesh,
                                            const polycube::CuboidLayout& layout,
                                            const CuboidSurfaceMapOptions& options) {
  const int n = mesh.num_vertices();
  CuboidSurfaceMap map;
  map.uvw = mesh::Positions::Zero(n, 3);
  map.face_region = layout.face_region;
  std::vector<char> fixed(n, 0);

  // Poly-edges by arc length: both rectangles sharing an edge read the same parameters.
  for (int e = 0; e < polycube::num_cube_edges; ++e) {
    const auto& path = layout.poly_edges[e];
    const int axis = e / 4;
    const int low = polycube::cube_edge_corners(e)[0];
    std::vector<double> arc(path.size(), 0.0);
    for (std::size_t i = 1; i < path.size(); ++i)
      arc[i] = arc[i - 1] + (mesh.vertex_position(path[i]) - mesh.vertex_position(path[i - 1])).norm();
    const double total = arc.back();
    for (std::size_t i = 0; i < path.size(); ++i) {
      Eigen::Vector3d uvw(low & 1, (low >> 1) & 1, (low >> 2) & 1);
      uvw(axis) = i + 1 == path.size() ? 1.0 : (total > 0.0 ? arc[i] / total : 0.0);
      map.uvw.row(path[i]) = uvw.transpose();
      fixed[path[i]] = 1;
    }
  }

  std::vector<double> weight;  // per halfedge, symmetric
  if (options.weights == SurfaceWeights::MeanValue) {
    // Symmetrized mean-value weights stay positive (Tutte's theorem needs only positivity) and
    // make the system SPD so the project's CG applies.
    const std::vector<double> mvc = mesh::mean_value_weights(mesh);
    weight.resize(mvc.size());
    for (int h = 0; h < mesh.num_halfedges(); ++h)
      weight[h] = 0.5 * (mvc[h] + mvc[mesh.halfedge_twin(h)]);
  } else {
    weight = mesh::edge_to_halfedge_weights(mesh, mesh::cotan_weights(mesh));
  }

  std::vector<int> vertex_face(n, -1);  // cube face of vertices inside a rectangle
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int v : mesh.face_vertices(f))
      if (!fixed[v]) vertex_face[v] = layout.face_region[f];

  std::vector<int> local(n, -1);
  for (int face = 0; face < polycube::num_cube_faces; ++face) {
    std::vector<int> interior;
    for (int v = 0; v < n; ++v)
      if (vertex_face[v] == face) {
        local[v] = static_cast<int>(interior.size());
        interior.push_back(v);
      }
    const int m = static_cast<int>(interior.size());
    if (m == 0) continue;
    std::vector<linalg::Triplet> triplets;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 2);
    for (int i = 0; i < m; ++i) {
      const int v = interior[i];
      double diagonal = 0.0;
      for (int h : mesh.vertex_outgoing(v)) {
        const int j = mesh.halfedge_vertex(h);
        const double w = weight[h];
        diagonal += w;
        if (fixed[j])
          rhs.row(i) += w * cube_face_coordinates(face, map.uvw.row(j).transpose()).transpose();
        else
          triplets.push_back({i, local[j], -w});
      }
      triplets.push_back({i, i, diagonal > 0.0 ? diagonal : 1.0});
    }
    const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(m, m, triplets);
    linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
    cg.set_tolerance(options.tolerance);
    cg.compute(a);
    // Warm start at the square's centre: the solution lies inside the square.
    const Eigen::MatrixXd st = cg.solve(rhs, Eigen::MatrixXd::Constant(m, 2, 0.5));
    if (cg.info() == linalg::SolverInfo::NumericalIssue)
      throw Error("mesh '" + mesh.source_name() + "': the harmonic map of cuboid face " +
                  std::to_string(face) + " has no SPD system (negative cotan weights?)");
    map.cg_iterations = std::max(map.cg_iterations, cg.iterations());
    for (int i = 0; i < m; ++i)
      map.uvw.row(interior[i]) = cube_face_point(face, st(i, 0), st(i, 1)).transpose();
    for (int v : interior) local[v] = -1;
  }

  int first_flipped = -1;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int face = layout.face_region[f];
    const auto c = mesh.face_vertices(f);
    const Eigen::Vector2d p0 = cube_face_coordinates(face, map.uvw.row(c[0]).transpose());
    const Eigen::Vector2d p1 = cube_face_coordinates(face, map.uvw.row(c[1]).transpose());
    const Eigen::Vector2d p2 = cube_face_coordinates(face, map.uvw.row(c[2]).transpose());
    const Eigen::Vector2d d1 = p1 - p0, d2 = p2 - p0;
    const double area = 0.5 * (d1.x() * d2.y() - d1.y() * d2.x());
    const double oriented = face % 2 == 1 ? area : -area;
    if (!(oriented > 0.0)) {
      ++map.num_flipped;
      if (first_flipped < 0) first_flipped = f;
    }
  }
  if (map.num_flipped > 0)
    throw Error("mesh '" + mesh.source_name() + "': the cuboid surface map is not bijective: " +
                std::to_string(map.num_flipped) + " flipped or degenerate triangles (first: face " +
                std::to_string(first_flipped) + " on cuboid face " +
                std::to_string(layout.face_region[first_flipped]) + ")");
  return map;
}

}  // namespace volspline::param
