// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh/triangle_mesh.h"
#include "core/param/gpc_volumetric_map.h"
#include "core/common/progress.h"
#include "core/polycube/gpc_builder.h"
#include "core/polycube/solid_decomposition.h"

namespace volspline::pipeline {

/// Default limb persistence: a branch of the graph distance at least this fraction of the
/// graph diameter long is a limb (armadillo's arms and legs, bunny's ears, dancer's hands and feet).
inline constexpr double kDefaultLimbPersistence = 0.15;

/// Limb persistence of the automatic retry: where the construction at kDefaultLimbPersistence
/// leaves inverted hexes, branches at least this fraction of the graph diameter long become caps
/// too (a suitcase's handle, a mug's), see GpcOptions::limb_persistence.
inline constexpr double kFinerLimbPersistence = 0.05;

/// Where the retry with taller T-shape centres puts their concave corners
/// (polycube::TShapeLayoutOptions::concave_corner_height), see GpcOptions::taller_centres_below.
inline constexpr double kTallerCentreHeight = 0.85;

/// How many times the first construction's least surface-map density (before the squeeze
/// rescue) the one with caps at the poles must reach to be kept, see GpcOptions::pole_caps_below.
inline constexpr double kPoleCapsGain = 10.0;

/// Pole offsets (polycube::MorseFunctionOptions::pole_offset) tried in this order where a genus > 0
/// solid has no construction with the poles at the graph diameter's ends, see
/// GpcStats::off_axis_poles. Which one works depends on where the levels cross the solid's bars
/// (a cube's wireframe: 0.08; stretched 3 %: 0.15; 10 %: 0.05), so several are tried.
inline constexpr std::array<double, 7> kOffAxisPoleOffsets = {0.08, 0.15, 0.05, 0.12, 0.2, 0.25, 0.3};

/// Options of run_gpc.
struct GpcOptions {
  /// Corner vertex ids (input numbering) of a genus-0 solid's one cuboid, in cube-corner order;
  /// empty = automatic. Ignored (refused) for genus > 0.
  std::vector<int> corners;
  param::GpcGridOptions grid;  ///< the volumetric grids (node budget, untangling)
  double snap = 0.05;          ///< level-set splitting snap, see split_at_level, in [0, 0.45)
  bool merge_cuboids = true;   ///< merge cuboids glued end to end across cuts (build_gpc)
  /// Cuts on the Morse function's level sets, or moved to the shortest loops that separate the
  /// same boundaries (tighten_cut_loops).
  polycube::CutPlacement cuts = polycube::CutPlacement::Shortest;
  /// Limb ends become caps: see MorseFunctionOptions::limb_persistence (fraction of the graph
  /// diameter, 0 = off; negative = kDefaultLimbPersistence, any genus; a genus-0 blob has no
  /// limb and stays one cuboid, as in mesh2spline). If that construction fails, or its hex mesh
  /// has inverted hexes after untangling and the two-pole one's has fewer (or as many and a
  /// higher least scaled Jacobian), the job keeps the two-pole one (a genus-0 solid: one cuboid,
  /// only if no limb construction was built when one_cuboid_fallback is OnlyIfUnbuilt) and says
  /// why in GpcStats::limb_fallback. Negative (automatic) only: if the hex mesh kept
  /// still has inverted hexes (untangler on) and kFinerLimbPersistence finds more limb tips, the
  /// limb construction at kFinerLimbPersistence is built and mapped too and the better hex mesh
  /// kept (fewer inverted hexes, then a higher least scaled Jacobian; a tie keeps the first), see
  /// GpcStats::finer_limbs.
  double limb_persistence = -1.0;
  /// Genus 0 only: whether a limb construction that was built may still give way to the two-pole
  /// one (one cuboid) because that hex mesh folds less. Off where the caller has already refused
  /// the one-cuboid map as squeezed (mesh2spline): one cuboid is then kept only if no limb
  /// construction can be built, since its few folds do not show the thin limbs it crowds.
  enum class OneCuboidFallback { ByFolds, OnlyIfUnbuilt };
  OneCuboidFallback one_cuboid_fallback = OneCuboidFallback::ByFolds;
  /// Scaled Jacobian in [−1, 1] (−1 = off): where the kept construction has T-shapes and its hex
  /// mesh (untangler on) has inverted hexes or a least scaled Jacobian below this, it is built and
  /// mapped again with every T-shape's concave corners at kTallerCentreHeight of the crotch's
  /// height and the better hex mesh kept (as for limbs), see GpcStats::taller_centres.
  double taller_centres_below = 0.2;
  /// Share of the hex mesh's hexes in (0, 1] (1 = off): the same retry also runs where the kept
  /// construction has T-shapes and more than this share of its hexes stay inverted, whatever
  /// taller_centres_below says. For a caller that leaves the hex mesh's few folds to a later
  /// stage but not a layout that folds the volume around a whole junction (mesh2spline).
  double taller_centres_inverted_above = 1.0;
  /// Linear parameter density in [0, 1) (0 = off): where the kept construction of a solid of
  /// genus > 0 has no cap and a cuboid's surface map has a spot below this density before the
  /// squeeze rescue (CuboidSurfaceMap::unrescued_least_density), it is built and mapped again
  /// with the two poles' pieces as caps (polycube::DecompositionOptions::pole_caps) and kept if
  /// that lifts the least unrescued density kPoleCapsGain times, see GpcStats::pole_caps.
  double pole_caps_below = 1e-3;
  int threads = 1;             ///< ≥ 1; the stages run on one thread (same output for any value)
};

/// Measures of a GPC construction (the names of DESIGN.md's GPC measures).
struct GpcStats {
  int genus = 0;
  int t_shapes = 0;
  int tubes = 0;
  int caps = 0;
  int cuboids = 0;
  int ill_points = 0;
  int interfaces = 0;
  int flipped_triangles = 0;
  int grid_inverted_hexes = 0;
  int grid_harmonic_inverted_hexes = 0;
  double grid_min_scaled_jacobian = 1.0;
  int cuboid_grid_inverted_hexes = 0;        ///< the cuboid grids without the padding layer
  double cuboid_grid_min_scaled_jacobian = 1.0;
  int padding_hexes = 0;                     ///< hexes of the padding layer (0 with it off)
  double interface_gap_rel = 0.0;
  /// polycube::face_area_ratios over the surface faces: least and largest (1 = balanced layout)
  double face_area_ratio_min = 1.0;
  double face_area_ratio_max = 1.0;
  int grid_nodes = 0;
  int shared_nodes = 0;
  int cut_disc_intersections = 0;  ///< meridian certificate: disc–surface/disc–disc crossings (must be 0)
  int cut_discs_outside = 0;       ///< discs outside the solid (must be 0)
  int tightened_cuts = 0;          ///< cuts moved off their level set to a shorter loop
  int flipped_cuts = 0;            ///< cuts replaced by a shorter one across the same two T-shapes (polycube::flip_cuts)
  double cut_length_rel = 0.0;     ///< summed length of the cuts over the bbox diagonal
  std::vector<int> cut_disc_crossings;  ///< per cut, its disc's crossing triangle pairs
  std::string cut_disc_problem;    ///< the first crossing or outside disc found, empty when embedded
  int num_saddles = 0;
  int limb_caps = 0;               ///< caps of the limb construction (0 if not used)
  std::string limb_fallback;       ///< why the limb construction was dropped (empty if not)
  double limb_persistence = 0.0;   ///< limb persistence of the construction kept (0: no limb caps)
  /// The retry at kFinerLimbPersistence: its inverted hexes and least scaled Jacobian and which
  /// construction was kept (empty if not tried).
  std::string finer_limbs;
  /// The retry with taller T-shape centres: its inverted hexes and least scaled Jacobian and
  /// which construction was kept (empty if not tried).
  std::string taller_centres;
  /// The retry with the poles' pieces as caps: its least surface-map density (before and after the
  /// squeeze rescue), its inverted hexes and which construction was kept (empty if not tried).
  std::string pole_caps;
  /// Where the poles moved off the graph diameter's ends (kOffAxisPoleOffsets): why the
  /// construction with the poles at its ends failed and the offset that worked (empty if they stayed).
  std::string off_axis_poles;
  int surface_vertices = 0;        ///< of the refined surface the cuboids partition
  std::map<std::string, double> times_s;
  /// The retried constructions' stats above that ran (non-empty), by their names, in this order:
  /// limb_fallback, finer_limbs, taller_centres, pole_caps, off_axis_poles.
  std::vector<std::pair<std::string, std::string>> retries() const {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& [name, text] : {std::pair<const char*, const std::string*>{"limb_fallback", &limb_fallback},
                                     {"finer_limbs", &finer_limbs},
                                     {"taller_centres", &taller_centres},
                                     {"pole_caps", &pole_caps},
                                     {"off_axis_poles", &off_axis_poles}})
      if (!text->empty()) out.emplace_back(name, *text);
    return out;
  }
};

/// The GPC domain of a solid and its volumetric parameterization, in model units.
struct GpcResult {
  polycube::GpcConstruction construction;  ///< domain graph, per-cuboid surfaces and layouts, discs
  param::GpcVolumetricMap map;             ///< per-cuboid surface maps and node grids
  mesh::TriangleMesh surface;              ///< the input surface refined along the cuts
  std::vector<int> face_cuboid;            ///< per face of `surface`, the cuboid it maps to
  GpcStats stats;
};

/// The `gpc` job (thesis ch. 3, §3.2–3.4): validate, decompose into caps, tubes and T-shapes
/// (Algorithm 1), T-to-cube (Algorithms 2, 3), check that every cut bounds a disc inside the
/// solid, map every cuboid (§3.4.1) and the volume (§3.4.2, Eq. 3.1) with the glued faces shared.
/// A genus-0 solid without cuts is one cuboid laid out exactly as mesh2spline does.
/// The input is centred and scaled to a unit diagonal inside; outputs are in model units.
/// Throws volspline::Error on bad input or options (exit 2), polycube::DecompositionError when
/// the construction fails (exit 1, naming the stage and the part), Cancelled.
GpcResult run_gpc(const mesh::TriangleMesh& input, const std::string& name, const GpcOptions& options = {},
                  const Progress& progress = {});

}  // namespace volspline::pipeline
