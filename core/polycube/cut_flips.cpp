// SPDX-License-Identifier: MIT
#include "core/polycube/cut_flips.h"

#include <cassert>

#include "core/polycube/cut_tightening.h"
#include "core/polycube/piece_resplit.h"

namespace volspline::polycube {

CutFlips flip_cuts(SolidDecomposition& d, const CutFlipOptions& options) {
  assert(options.max_passes >= 0 && options.max_length_ratio > 0.0 && options.max_length_ratio <= 1.0);
  CutFlips out;
  out.length_before = cut_length(d);
  ResplitOptions resplit;
  resplit.snap = options.snap;
  for (int pass = 0; pass < options.max_passes; ++pass) {
    int flipped = 0;
    for (std::size_t l = 0; l < d.loops.size(); ++l) {
      const auto [a, b] = d.loops[l].piece;
      if (a == b || d.pieces[a].kind != PieceKind::TShape || d.pieces[b].kind != PieceKind::TShape) continue;
      SolidDecomposition trial = d;
      if (!resplit_across_loop(trial, static_cast<int>(l), resplit)) continue;
      tighten_cut_loops(trial, true, static_cast<int>(l));
      if (loop_length(trial.mesh, trial.loops[l].vertices) >=
          options.max_length_ratio * loop_length(d.mesh, d.loops[l].vertices))
        continue;
      d = std::move(trial);
      ++flipped;
    }
    out.num_flipped += flipped;
    if (flipped == 0) break;
  }
  out.length_after = cut_length(d);
  return out;
}

}  // namespace volspline::polycube
