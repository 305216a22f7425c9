// SPDX-License-Identifier: MIT
#include "core/param/volumetric_grid_map.h"

#include <algorithm>
#include <string>

#include <Eigen/LU>

#include "core/common/error.h"
#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/mesh/hex_quality.h"
#include "core/param/hex_grid_untangling.h"

namespace volspline::param {

VolumetricGridMap compute_volumetric_grid_map(const CuboidSurfaceLocator& locator,
                                              const VolumetricGridOptions& options) {
  for (int a = 0; a < 3; ++a)
    if (options.nodes[a] < 2 || options.nodes[a] > 1024)
      throw Error("volumetric grid: " + std::to_string(options.nodes[a]) + " nodes along axis " +
                  std::to_string(a) + " (expected 2..1024)");
  const std::array<int, 3> n = options.nodes;
  VolumetricGridMap grid;
  grid.nodes = n;
  const int total = n[0] * n[1] * n[2];
  grid.xyz = mesh::Positions::Zero(total, 3);
  auto param = [&](int i, int a) { return static_cast<double>(i) / (n[a] - 1); };
  std::vector<int> unknown(total, -1);
  int num_interior = 0;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const int id = grid_node_index(n, i, j, k);
        const bool boundary = i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 ||
                              k == n[2] - 1;
        if (boundary)
          grid.xyz.row(id) =
              locator.locate_uvw(Eigen::Vector3d(param(i, 0), param(j, 1), param(k, 2))).transpose();
        else
          unknown[id] = num_interior++;
      }
  if (num_interior > 0) {
    // Warm start: mean of the three axis-wise linear interpolations between opposite faces.
    Eigen::MatrixXd x0(num_interior, 3);
    std::vector<linalg::Triplet> triplets;
    triplets.reserve(7 * static_cast<std::size_t>(num_interior));
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(num_interior, 3);
    for (int k = 1; k < n[2] - 1; ++k)
      for (int j = 1; j < n[1] - 1; ++j)
        for (int i = 1; i < n[0] - 1; ++i) {
          const int id = grid_node_index(n, i, j, k);
          const int row = unknown[id];
          const std::array<int, 3> ijk = {i, j, k};
          Eigen::Vector3d guess = Eigen::Vector3d::Zero();
          for (int a = 0; a < 3; ++a) {
            std::array<int, 3> lo = ijk, hi = ijk;
            lo[a] = 0;
            hi[a] = n[a] - 1;
            const double t = param(ijk[a], a);
            guess += (1.0 - t) * grid.xyz.row(grid_node_index(n, lo[0], lo[1], lo[2])).transpose() +
                     t * grid.xyz.row(grid_node_index(n, hi[0], hi[1], hi[2])).transpose();
          }
          x0.row(row) = guess.transpose() / 3.0;
          // Eq. 3.1 with uniform weights 1/6: 6 x_ijk − Σ neighbours = 0.
          triplets.push_back({row, row, 6.0});
          for (int a = 0; a < 3; ++a)
            for (int step : {-1, 1}) {
              std::array<int, 3> nb = ijk;
              nb[a] += step;
              const int nid = grid_node_index(n, nb[0], nb[1], nb[2]);
              if (unknown[nid] >= 0)
                triplets.push_back({row, unknown[nid], -1.0});
              else
                rhs.row(row) += grid.xyz.row(nid);
            }
        }
    const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(num_interior, num_interior, triplets);
    linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
    cg.set_tolerance(options.tolerance);
    cg.compute(a);
    const Eigen::MatrixXd x = cg.solve(rhs, x0);
    grid.cg_iterations = cg.iterations();
    grid.converged = cg.info() == linalg::SolverInfo::Success;
    for (int id = 0; id < total; ++id)
      if (unknown[id] >= 0) grid.xyz.row(id) = x.row(unknown[id]);
  } else {
    grid.converged = true;
  }

  auto check_hexes = [&] {
    const mesh::HexGridQuality q = mesh::hex_grid_quality(n, grid.xyz);
    grid.num_hexes = q.num_hexes;
    grid.num_inverted_hexes = q.num_inverted;
    grid.min_scaled_jacobian = q.min_scaled_jacobian;
  };
  check_hexes();
  grid.harmonic_inverted_hexes = grid.num_inverted_hexes;
  if (options.untangle == VolumetricGridOptions::Untangle::On && grid.num_inverted_hexes > 0 && num_interior > 0) {
    // §3.4.2 takes the harmonic nodes as they are; the fit would copy their folds into the
    // spline, so they are untangled first (the harmonic grid is the start).
    std::vector<char> fixed(total);
    for (int id = 0; id < total; ++id) fixed[id] = unknown[id] < 0;
    grid.untangled_nodes = untangle_hex_grid(n, fixed, grid.xyz).free_nodes;
    check_hexes();
  }
  return grid;
}

}  // namespace volspline::param
