// SPDX-License-Identifier: MIT
#pragma once

#include "core/polycube/solid_decomposition.h"

namespace volspline::polycube {

/// What flip_cuts did.
struct CutFlips {
  int num_flipped = 0;         ///< cuts replaced by a shorter meridian across the same two T-shapes
  double length_before = 0.0;  ///< summed length of all cuts before (model units)
  double length_after = 0.0;   ///< and after
};

/// Options of flip_cuts.
struct CutFlipOptions {
  int max_passes = 3;     ///< passes over the cuts; a pass that flips none ends the search
  /// A flip is kept when the new cut is shorter than this fraction of the old one (unitless, in
  /// (0, 1]): small gains are not worth a different layout.
  double max_length_ratio = 0.9;
  double snap = 0.05;     ///< see ResplitOptions::snap, in [0, 0.45)
};

/// §3.3.1 fixes the pieces (caps, tubes, T-shapes) but not which pants decomposition cuts them.
/// A cut re-split across two T-shapes (resplit_across_loop) sits midway between the saddles of
/// the merged piece's harmonic function, which can lie next to one pair of its loops: the cut
/// then runs beside them and leaves a sliver T-shape between two nearly parallel cuts, whose
/// layout finds no disjoint seams (a plate with a grid of holes). The elementary move of pants
/// decompositions undoes that: each cut between two distinct T-shapes is re-split across their
/// union (the best meridian over its 3 pairings) and moved to its shortest loop
/// (tighten_cut_loops, that cut only); the result is kept when the cut is shorter than
/// max_length_ratio of its old length. Both steps keep every cut a meridian and every piece a
/// planar T-shape with its loops (each checks that itself). Cuts are visited in order, each
/// seeing the ones flipped before it (deterministic).
/// Preconditions: `decomposition` as decompose_solid returns it (closed mesh, every cut certified).
CutFlips flip_cuts(SolidDecomposition& decomposition, const CutFlipOptions& options = {});

}  // namespace volspline::polycube
