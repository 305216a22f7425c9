// SPDX-License-Identifier: MIT
#pragma once

#include "core/polycube/solid_decomposition.h"

namespace volspline::polycube {

/// What tighten_cut_loops did.
struct CutTightening {
  int num_tightened = 0;        ///< cuts replaced by a shorter loop
  double length_before = 0.0;   ///< summed length of all cuts before (model units)
  double length_after = 0.0;    ///< and after
};

/// §3.3.1 cuts the solid along level-set loops; a level set of the Morse function follows the
/// function, not the shape, and runs diagonally through a thick part, so its disc bends and may
/// cross the surface. Here every cut between two pieces that each hold another boundary loop
/// (or a tube closed on itself) moves to the shortest loop along mesh edges of the two pieces
/// that separates the same boundary loops: a minimum cut of the dual graph with edge lengths as
/// capacities, edges touching another cut uncuttable. The cut of a cap (a limb's end) moves to
/// the shortest loop within a band a quarter of its length wide around it, whose rim on the
/// cap's side is the cap's terminal (`caps` false: caps' cuts stay). In the planar union of the two pieces every
/// such loop bounds a disc in the solid (the union with its other cuts' discs bounds a ball) and
/// leaves both pieces with their boundary loops, so the decomposition's topology is kept. A new
/// loop is taken only when it is one simple loop, the pieces stay planar, and its interface disc
/// is no worse under the meridian certificate (check_loop_disc: inside, no more crossings).
/// The cut of a tube closed on itself (its one cuboid's only cut, which sets its cross-section)
/// stays unless its disc crosses the surface.
/// Cuts are visited in order and each sees the ones moved before it (deterministic).
/// A moved loop is no longer a level set: CutLoop::level keeps the level it was cut at.
/// `only_loop` ≥ 0: that cut alone is visited.
CutTightening tighten_cut_loops(SolidDecomposition& decomposition, bool caps = true, int only_loop = -1);

}  // namespace volspline::polycube
