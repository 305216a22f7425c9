// SPDX-License-Identifier: MIT
#pragma once

#include <array>

#include "core/mesh/triangle_mesh.h"
#include "core/param/cuboid_surface_locator.h"

namespace volspline::param {

/// Options of compute_volumetric_grid_map.
struct VolumetricGridOptions {
  std::array<int, 3> nodes = {17, 17, 17};  ///< n0, n1, n2 grid nodes per axis, each ≥ 2
  double tolerance = 1e-8;                  ///< relative CG residual (unitless)
  /// Remove the folds of the harmonic grid near its folded hexes (untangle_hex_grid); off =
  /// the thesis's map as it is.
  enum class Untangle { Off, On } untangle = Untangle::On;
};

/// Node positions of a uniform parameter grid mapped into the solid (thesis §3.4.2).
struct VolumetricGridMap {
  std::array<int, 3> nodes{};  ///< n0, n1, n2
  /// (n0·n1·n2)×3 positions, model units; node (i, j, k) at row i + n0·(j + n1·k), parameter
  /// (i/(n0−1), j/(n1−1), k/(n2−1)).
  mesh::Positions xyz;
  int num_hexes = 0;
  int num_inverted_hexes = 0;         ///< hexes with a corner Jacobian ≤ 0
  int harmonic_inverted_hexes = 0;    ///< the same for the harmonic grid of Eq. 3.1, before untangling
  int untangled_nodes = 0;            ///< interior nodes the untangling moved
  double min_scaled_jacobian = 1.0;   ///< over the 8 corners of every hex, in [−1, 1]
  int cg_iterations = 0;
  bool converged = false;
};

/// Row of node (i, j, k) in VolumetricGridMap::xyz.
inline int grid_node_index(const std::array<int, 3>& nodes, int i, int j, int k) {
  return i + nodes[0] * (j + nodes[1] * k);
}

/// Boundary nodes by inverse lookup in the surface map, interior nodes minimizing the uniform
/// 6-neighbour Laplacian energy of Eq. 3.1 (one SPD solve by CG with IC(0), warm-started from
/// transfinite interpolation, instead of the thesis' Jacobi sweeps). The harmonic grid folds
/// where the surface is concave at the grid's scale (ears, creases); with options.untangle the
/// interior nodes near folded hexes are then moved by untangle_hex_grid. Every hex is checked for
/// positive corner Jacobians (remaining folds are reported, not an error; corners of boundary
/// nodes only, along the cuboid's edges, cannot move). Throws volspline::Error if a node count is < 2 or > 1024.
VolumetricGridMap compute_volumetric_grid_map(const CuboidSurfaceLocator& locator,
                                              const VolumetricGridOptions& options = {});

}  // namespace volspline::param
