// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "core/common/progress.h"
#include "core/mesh/triangle_mesh.h"

namespace volspline::param {

/// Options of untangle_hex_grid.
struct HexGridUntangleOptions {
  /// Free nodes: the movable nodes within this many grid steps (Chebyshev) of a node of a hex
  /// with an inverted movable corner, ≥ 1, taken again after every ε step (so the free region
  /// shrinks as folds open); doubled (at most twice) while folds remain that the region's
  /// border held.
  int rings = 2;
  int rounds = 3;              ///< at most this many rounds of doubling `rings`, ≥ 1
  int max_steps = 40;          ///< ε-continuation steps, ≥ 1
  int max_inner = 30;          ///< L-BFGS iterations per step, ≥ 1
  /// Weight θ of the volume term (det² + 1)/χ against the shape term tr(JᵀJ)/χ^(2/3), in [0, 1).
  double volume_weight = 0.5;
  /// Sliding nodes: after every accepted L-BFGS step their unknowns are set to the surface
  /// points they stand for. Off the surface, an unknown drifts into the wedge of an edge or vertex
  /// of the surface mesh, where its projection no longer follows the tangent-plane gradient and
  /// the line search backtracks on most steps; settled, the steps are far fewer, on another path.
  bool settle_sliding = false;
  /// The reference cell of each hex's corner terms. MeanCell: one cube of the mean corner volume
  /// for all hexes, so det J ≈ 1 on average and the volume term asks for cells of even size (a
  /// structured grid's spacing). OwnCell (untangle_hex_mesh only): a cube whose edge is the hex's own
  /// mean edge length on entry, so the barrier's ε and the volume term act at every hex's own scale;
  /// in a mesh whose cells differ in size by orders of magnitude (thin limbs beside a body,
  /// padding hexes) a global reference leaves small hexes' determinants far below ε, where the
  /// barrier does not see their sign.
  enum class Reference { MeanCell, OwnCell } reference = Reference::MeanCell;
};

/// Nodes of untangle_hex_mesh that slide on a surface or a curve: slides[v] flags node v;
/// project(v, p, tangent) returns the point of v's surface or curve nearest to p and writes the
/// orthogonal projector onto the tangent space there (I − n nᵀ on a surface with unit normal n,
/// t tᵀ on a curve with unit tangent t). Positions of flagged nodes must lie on them on entry.
struct SlidingNodes {
  std::vector<char> slides;
  std::function<Eigen::Vector3d(int node, const Eigen::Vector3d& p, Eigen::Matrix3d* tangent)> project;
};

/// Outcome of untangle_hex_grid. A corner is "movable" if one of its 4 nodes is not fixed;
/// corners of fixed nodes only (e.g. along the edges of a cuboid map) are left as they are.
struct HexGridUntangleReport {
  int initial_inverted = 0;  ///< movable corners with det ≤ 0 before
  int final_inverted = 0;    ///< and after
  int free_nodes = 0;        ///< nodes the last round's first step moved
  int iterations = 0;        ///< L-BFGS iterations, all rounds
};

/// Removes the folds of a structured hex grid by moving its non-fixed nodes near the folds:
/// minimizes the regularized shape + volume energy of "Foldover-free maps in 50 lines of code"
/// (Garanzha et al. 2021) over the 8 corner tetrahedra of every hex, with the barrier
/// χ(D, ε) = (D + √(ε² + D²))/2 in place of det J and ε decreased as the paper prescribes, by
/// L-BFGS. The energy is finite for folded cells, so it starts from any grid, and its minimizers
/// for ε → 0 have det J > 0 at every movable corner when a fold-free placement exists.
/// Nodes far from folds are not moved. The continuation stops as untangle does, and also once
/// the number of folded corners has not reached a new low for 3 steps (corners that cannot
/// unfold, e.g. of hexes along a cuboid edge with 6 fixed nodes, remain folded). Corner c of hex (i, j, k) is node (i + (c&1), j +
/// (c>>1&1), k + (c>>2&1)); its Jacobian has the three hex edges leaving it along +axis
/// orientation, as mesh::hex_min_scaled_jacobian. nodes: n0, n1, n2 ≥ 2; xyz: (n0·n1·n2)×3 in the
/// order of grid_node_index, changed in place; fixed: one flag per node.
/// progress: "grid untangling" before every ε step, the fraction of rounds × max_steps done;
/// throws volspline::Cancelled there if it asks to stop (xyz then holds the last step's nodes).
HexGridUntangleReport untangle_hex_grid(const std::array<int, 3>& nodes, const std::vector<char>& fixed,
                                        mesh::Positions& xyz, const HexGridUntangleOptions& options = {},
                                        const Progress& progress = {});

/// untangle_hex_grid on hexes that need not form one grid (the cuboid grids of a generalized
/// poly-cube with their glued nodes shared): hexes[h] lists hex h's 8 node ids, node q at offset
/// (q&1, q>>1&1, q>>2&1), into xyz (changed in place); fixed: one flag per node. The free region
/// grows by rings of hexes through shared nodes. `near` (per node, or empty = everywhere): only
/// folds within options.rings hexes of a flagged node are worked on (and counted in the report).
/// sliding (or null): nodes that are not fixed and flagged there stay on their surface or curve,
/// at the projection of where the optimizer puts them, their gradient taken in the tangent space.
/// progress: as untangle_hex_grid.
HexGridUntangleReport untangle_hex_mesh(const std::vector<std::array<int, 8>>& hexes, const std::vector<char>& fixed,
                                        mesh::Positions& xyz, const std::vector<char>& near = {},
                                        const HexGridUntangleOptions& options = {},
                                        const SlidingNodes* sliding = nullptr, const Progress& progress = {});

/// Raises the quality of a fold-free hex mesh: at most `iterations` L-BFGS iterations on the
/// energy of untangle_hex_mesh at ε = 1e-8 over every node that is not fixed (sliding nodes as
/// there), whose barrier keeps every corner unfolded. The shape term tr(JᵀJ)/det^(2/3) is
/// least for a cube corner, so the worst corners open up. Returns the iterations done (0 if the
/// mesh has a folded corner or nothing is free). Arguments as untangle_hex_mesh.
int improve_hex_mesh(const std::vector<std::array<int, 8>>& hexes, const std::vector<char>& fixed,
                     mesh::Positions& xyz, int iterations, double volume_weight = 0.5,
                     const SlidingNodes* sliding = nullptr);

}  // namespace volspline::param
