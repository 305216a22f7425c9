// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/mesh/halfedge_mesh.h"
#include "core/polycube/morse_function.h"

namespace volspline::polycube {

/// A decomposition step could not produce valid pieces (a job failure, exit code 1): the
/// message names the stage and the part. refinable: whether the step may succeed on the surface
/// subdivided (subdivide_decomposition), false where refining is known not to help.
class DecompositionError : public std::runtime_error {
 public:
  explicit DecompositionError(const std::string& message, bool refinable = true)
      : std::runtime_error(message), refinable_(refinable) {}
  bool refinable() const { return refinable_; }

 private:
  bool refinable_ = true;
};

/// What a piece of the decomposition is (§3.3.1): by its number of boundary loops.
enum class PieceKind {
  Solid = 0,   ///< no loop: the whole genus-0 solid (one cuboid, as a blob)
  Cap = 1,     ///< a disc: one loop
  Tube = 2,    ///< an annulus: two loops (both may be the same cut: a tube closed on itself)
  TShape = 3,  ///< a pair of pants: three loops
};

/// A closed curve on the surface along which the solid is cut.
struct CutLoop {
  /// Vertex cycle in SolidDecomposition::mesh (first vertex not repeated), in the direction of
  /// the halfedges of the faces below the level (value < level), which lie on its left.
  std::vector<int> vertices;
  /// Value of the Morse function on the loop; for a cut replaced by resplit_across_loop, the
  /// level of its merged piece's harmonic function instead (not of SolidDecomposition::value);
  /// for one replaced by replace_handle_cut, 0.5 (SolidDecomposition::value is then redefined).
  double level = 0.0;
  std::array<int, 2> piece{-1, -1};  ///< piece below and piece above (may be equal)
};

/// One side of a cut loop as a boundary of a piece.
struct LoopSide {
  int loop = -1;
  int side = 0;  ///< 0: the piece lies below the loop's level, 1: above
};

/// A planar piece of the surface: a cap, a tube or a T-shape (or the whole genus-0 surface).
struct SolidPiece {
  std::vector<int> faces;         ///< faces of SolidDecomposition::mesh, ascending
  std::vector<LoopSide> boundary; ///< its boundary loops, ascending by (loop, side)
  PieceKind kind = PieceKind::Solid;
};

/// The surface cut into caps, tubes and T-shapes along level-set loops.
struct SolidDecomposition {
  mesh::TriangleMesh mesh;      ///< the input surface refined so that every cut runs along edges
  std::vector<double> value;    ///< the Morse function per vertex of `mesh` (see replace_handle_cut)
  std::vector<int> parent_face; ///< per face of `mesh`, the input face it lies in
  std::vector<CutLoop> loops;   ///< the kept cuts
  std::vector<SolidPiece> pieces;
  int genus = 0;
  int num_saddles = 0;          ///< of the Morse function, with multiplicity (= 2·genus)
  int num_levels = 0;           ///< levels cut before merging
  int num_initial_pieces = 0;   ///< pieces before merging
  int num_resplit_cuts = 0;     ///< level-set cuts that failed the meridian certificate and were replaced
  int num_tightened_cuts = 0;   ///< cuts moved off their level set to a shorter loop (CutPlacement::Shortest)
  /// `mesh` with its halfedges, when the caller has them (build_gpc then does not build them
  /// again: a 1.3M-triangle surface takes 0.4 s), or null. Only for an uncut solid.
  std::shared_ptr<const mesh::HalfedgeMesh> halfedges;
};

/// Where decompose_solid puts its cuts.
enum class CutPlacement {
  LevelSet,  ///< on the level sets of the Morse function (Algorithm 1 as written)
  Shortest,  ///< moved to the shortest loops that separate the same boundaries (tighten_cut_loops)
};

/// Options of decompose_solid.
struct DecompositionOptions {
  double snap = 0.05;  ///< see split_at_level, in [0, 0.45)
  CutPlacement cuts = CutPlacement::Shortest;
  bool tighten_caps = true;  ///< with CutPlacement::Shortest, caps' cuts move too (tighten_cut_loops)
  MorseFunctionOptions morse;  ///< the Morse function (limb poles: morse.limb_persistence)
  /// The pieces around the two poles stay caps even without limb tips (as limb ends do), so that
  /// a limb at the graph diameter's end (two temples on a pair of rings) is a cap of its own
  /// instead of part of the T-shape it hangs from.
  bool pole_caps = false;
};

/// §3.3.1, Algorithm 1, by level sets of a fair Morse function (see compute_morse_function):
/// the surface is cut at one level between every two consecutive critical values, so each piece
/// holds one critical point (a disc around an extremum, an annulus, or a pair of pants around a
/// simple saddle), then cuts are removed greedily, the one giving the fewest boundary loops first,
/// while the merged piece keeps ≤ 3 loops and the two sides differ (a cut between a piece and
/// itself would add a handle). Every piece is planar (checked: genus 0 by its Euler
/// characteristic). Every kept loop bounds a disc inside the solid: it passes the meridian
/// certificate (check_loop_disc) or is replaced by a cut that passes it (resplit_across_loop,
/// replace_handle_cut).
/// Count check: #T-shapes = #caps + 2g − 2.
/// Preconditions: `mesh` closed, connected, consistently and outward oriented.
/// A piece with 4 loops (two saddles at one level, or a degenerate saddle) is split into two
/// T-shapes by a meridian across it (split_four_holed_piece).
/// Throws DecompositionError if a piece is not planar, has more than 4 loops or 4 that no
/// meridian splits, naming the piece, or if a kept loop fails the meridian certificate and no
/// replacement passes it, naming the cut.
SolidDecomposition decompose_solid(const mesh::HalfedgeMesh& mesh, int genus,
                                   const DecompositionOptions& options = {});

/// Splits every triangle of the decomposition into 4 at its edge midpoints (the surface and the
/// cuts stay where they are; cut loops get their edges' midpoints), for pieces too coarse to
/// hold the disjoint paths of a T-shape's layout.
void subdivide_decomposition(SolidDecomposition& decomposition);

/// Length of a closed vertex cycle of `mesh` (a cut loop; first vertex not repeated), in the
/// mesh's units.
double loop_length(const mesh::TriangleMesh& mesh, const std::vector<int>& loop);

/// Summed length of the decomposition's cuts, in its mesh's units.
double cut_length(const SolidDecomposition& decomposition);

}  // namespace volspline::polycube
