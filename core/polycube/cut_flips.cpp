// SPDX-License-Identifier: MIT
#include "core/polycube/cut_flips.h"

#include <array>
#include <cassert>
#include <vector>

#include "core/polycube/cut_tightening.h"
#include "core/polycube/piece_resplit.h"

namespace volspline::polycube {

CutFlips flip_cuts(SolidDecomposition& d, const CutFlipOptions& options) {
  assert(options.max_passes >= 0 && options.max_length_ratio > 0.0 && options.max_length_ratio <= 1.0);
  CutFlips out;
  out.length_before = cut_length(d);
  ResplitOptions resplit;
  resplit.snap = options.snap;
  // A cut is tried again only after a flip changed one of its two pieces since its last trial. A
  // trial reads those pieces (faces, loops, the mesh inside them), and a flip changes only its
  // own two pieces (others keep their face and vertex ids), so the trial would fail again; only
  // the certificate's crossing counts see the rest of the surface, and there a flip re-triangulates
  // but does not move it.
  std::vector<int> version(d.pieces.size(), 0);
  std::vector<std::array<int, 2>> tried_at(d.loops.size(), {-1, -1});
  for (int pass = 0; pass < options.max_passes; ++pass) {
    int flipped = 0;
    for (std::size_t l = 0; l < d.loops.size(); ++l) {
      const auto [a, b] = d.loops[l].piece;
      if (a == b || d.pieces[a].kind != PieceKind::TShape || d.pieces[b].kind != PieceKind::TShape) continue;
      const std::array<int, 2> seen{version[a], version[b]};
      if (tried_at[l] == seen) continue;
      tried_at[l] = seen;
      SolidDecomposition trial = d;
      if (!resplit_across_loop(trial, static_cast<int>(l), resplit)) continue;
      tighten_cut_loops(trial, true, static_cast<int>(l));
      if (loop_length(trial.mesh, trial.loops[l].vertices) >=
          options.max_length_ratio * loop_length(d.mesh, d.loops[l].vertices))
        continue;
      d = std::move(trial);
      ++version[a];
      ++version[b];
      ++flipped;
    }
    out.num_flipped += flipped;
    if (flipped == 0) break;
  }
  out.length_after = cut_length(d);
  return out;
}

}  // namespace volspline::polycube
