// SPDX-License-Identifier: MIT
#pragma once

#include <vector>

#include "core/mesh/halfedge_mesh.h"

namespace volspline::polycube {

/// A map of an annulus onto the cylinder [0, 1] × (ℝ / ℤ).
struct CylinderMap {
  std::vector<double> u;  ///< per vertex, 0 on the first loop, 1 on the second
  std::vector<double> v;  ///< per vertex, angular coordinate in [0, 1)
  std::vector<int> cut;   ///< the vertex path from the first loop to the second that was cut open
  double length = 0.0;        ///< cut path length (model units): the annulus's height
  double circumference = 0.0; ///< mean length of the two loops (model units)
};

/// The cylinder parameterization of §3.3.2 step 3 (after Li et al.): the annulus is cut open
/// along the shortest edge path between its loops into a disc, and the disc is mapped to the
/// unit square by Floater's mean-value convex combination map (bijective by Tutte's theorem)
/// with the first loop on u = 0, the second on u = 1, the two sides of the cut on v = 0 and
/// v = 1, each side by arc length. Differs from the thesis's two harmonic solves (Δu = 0, then
/// Δv = 0 with the cut) only in solving both at once on the cut disc, which gives the same u up
/// to the boundary condition along the cut and guarantees a bijection.
/// Preconditions: `mesh` is an annulus (2 boundary loops, genus 0); `loop_a`, `loop_b` list the
/// vertices of its two boundary loops. Deterministic.
CylinderMap compute_cylinder_map(const mesh::HalfedgeMesh& mesh, const std::vector<int>& loop_a,
                                 const std::vector<int>& loop_b);

}  // namespace volspline::polycube
