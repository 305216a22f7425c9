// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/polycube/solid_decomposition.h"

namespace volspline::polycube {

/// Options of resplit_across_loop.
struct ResplitOptions {
  double snap = 0.05;         ///< see split_at_level, in [0, 0.45)
  double tolerance = 1e-12;   ///< relative CG residual of the harmonic solve (unitless)
};

/// Replaces cut `loop` of `d`, which separates two distinct T-shapes, by a cut across the same
/// merged piece that bounds a disc inside the solid (§3.3.1: every cut is a meridian). The two
/// T-shapes together are a sphere with 4 holes; for each of the 3 ways to pair its boundary
/// loops, the harmonic function u (symmetrized mean-value weights) that is 0 on one pair and 1 on
/// the other is cut midway between the values of its 2 saddles (−χ; no interior extremum by the
/// maximum principle), where its level set can be one loop separating the pairs (split_at_level,
/// boundary frozen; 1/2 if the saddles coincide). A pairing qualifies when that level set is a
/// single loop (so each side is a pair of pants holding one pair) whose interface disc passes the
/// meridian certificate (check_loop_disc: centre winding number ≥ 1/2). The qualifying disc with the fewest surface crossings wins, then the
/// shortest loop, then the first pairing. On success `d.mesh` is refined inside the merged piece
/// (other face and vertex ids unchanged), `d.value` is extended linearly along split edges,
/// `d.parent_face`, the loop (`level`: the level of u; piece[0] holds the pair at u = 0), both pieces and
/// the sides of their other loops are updated, and true is returned. Otherwise `d` is unchanged
/// and *why (if given) says why. Precondition: 0 ≤ loop < d.loops.size(), d.mesh closed.
bool resplit_across_loop(SolidDecomposition& d, int loop, const ResplitOptions& options = {},
                         std::string* why = nullptr);

/// Splits piece `piece` of `d`, a sphere with 4 holes (a degenerate saddle, or two saddles at
/// one level, leave such a piece between two levels), into two T-shapes along a new cut appended
/// to `d.loops` (its piece[0] is `piece`, holding the pair at u = 0; piece[1] a new piece
/// appended to `d.pieces`), chosen as resplit_across_loop chooses its cut. Returns false with
/// *why (if given) and `d` unchanged when the piece has not 4 loops or no pairing gives a
/// meridian. Precondition: 0 ≤ piece < d.pieces.size(), d.mesh closed.
bool split_four_holed_piece(SolidDecomposition& d, int piece, const ResplitOptions& options = {},
                            std::string* why = nullptr);

/// Replaces cut `loop` of `d` whose both sides bound the same tube (a genus-1 solid cut along a
/// loop that is no meridian, e.g. a longitude of a tall pipe) by a loop that crosses it once and
/// passes the meridian certificate (§3.3.1: every cut is a meridian). Candidates: for each loop
/// vertex p, the shortest edge path through the tube (cut open along the loop) from one copy of p
/// to the other, not touching the loop elsewhere, closed at p; the 8 shortest are certified
/// (check_loop_disc: centre winding number ≥ 1/2) and the one with the fewest crossings, then the
/// shortest, wins. The mesh stays as it is; `d.value` becomes, on the tube cut open along the new
/// loop, the harmonic function (symmetrized mean-value weights) 0 on its left copy and 1 on its
/// right one, with 1/2 on the loop (its `level`), so the loop's sides are told apart by value as
/// for a level set. Returns false with *why (if given) and `d` unchanged when the sides are not one
/// tube or no candidate passes. Precondition: 0 ≤ loop < d.loops.size(), d.mesh closed.
bool replace_handle_cut(SolidDecomposition& d, int loop, std::string* why = nullptr);

}  // namespace volspline::polycube
