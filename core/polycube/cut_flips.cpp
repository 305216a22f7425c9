// SPDX-License-Identifier: MIT
#include "core/polycube/cut_flips.h"

#include <cassert>

#include "core/polycube/cut_tightening.h"
#include "core/polycube/piece_resplit.h"

namespace volspline::polycube {

namespace {

double loop_length(const mesh::TriangleMesh& m, const std::vector<int>& loop) {
  double total = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i)
    total += (m.positions.row(loop[i]) - m.positions.row(loop[(i + 1) % loop.size()])).norm();
  return total;
}

double summed_length(const SolidDecomposition& d) {
  double total = 0.0;
  for (const CutLoop& l : d.loops) total += loop_length(d.mesh, l.vertices);
  return total;
}

}  // namespace

CutFlips flip_cuts(SolidDecomposition& d, const CutFlipOptions& options) {
  assert(options.max_passes >= 0 && options.max_length_ratio > 0.0 && options.max_length_ratio <= 1.0);
  CutFlips out;
  out.length_before = summed_length(d);
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
  out.length_after = summed_length(d);
  return out;
}

}  // namespace volspline::polycube
