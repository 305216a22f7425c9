// SPDX-License-Identifier: MIT
#include "core/pipeline/gpc_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <sstream>

#include "core/common/error.h"
#include "core/pipeline/solid_mesh.h"
#include "core/polycube/cut_flips.h"
#include "core/polycube/interface_disc.h"
#include "core/polycube/solid_decomposition.h"

namespace volspline::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void check_options(const GpcOptions& o) {
  auto fail = [](const std::string& what) { throw Error("gpc: " + what); };
  if (o.threads < 1) fail("threads must be ≥ 1");
  if (!(o.snap >= 0.0 && o.snap < 0.45)) fail("snap must be in [0, 0.45)");
  if (o.grid.target_nodes < 64 || o.grid.target_nodes > 20000000) fail("grid.target_nodes must be in [64, 2e7]");
  if (o.grid.min_nodes < 2 || o.grid.max_nodes < o.grid.min_nodes || o.grid.max_nodes > 1024)
    fail("grid.min_nodes must be ≥ 2 and ≤ grid.max_nodes ≤ 1024");
  if (!(o.grid.tolerance > 0.0 && o.grid.tolerance < 1.0)) fail("grid.tolerance must be in (0, 1)");
  if (o.grid.area_balance_iterations < 0 || o.grid.area_balance_iterations > 20)
    fail("grid.area_balance_iterations must be in [0, 20]");
  if (!(o.grid.squeezed_below >= 0.0 && o.grid.squeezed_below < 1.0)) fail("grid.squeezed_below must be in [0, 1)");
  if (!(o.grid.padding_depth > 0.0 && o.grid.padding_depth < 1.0)) fail("grid.padding_depth must be in (0, 1)");
  if (o.grid.quality_iterations < 0 || o.grid.quality_iterations > 100000)
    fail("grid.quality_iterations must be in [0, 100000]");
  if (!(o.grid.min_quality_target > -1.0 && o.grid.min_quality_target <= 1.0))
    fail("grid.min_quality_target must be in (-1, 1]");
  if (!(o.grid.wider_relax_below >= -1.0 && o.grid.wider_relax_below <= 1.0))
    fail("grid.wider_relax_below must be in [-1, 1]");
  if (o.grid.min_quality_sweeps < 0 || o.grid.min_quality_sweeps > 100000)
    fail("grid.min_quality_sweeps must be in [0, 100000]");
  if (!(o.taller_centres_below >= -1.0 && o.taller_centres_below <= 1.0)) fail("taller_centres_below must be in [-1, 1]");
  if (!(o.taller_centres_inverted_above > 0.0 && o.taller_centres_inverted_above <= 1.0))
    fail("taller_centres_inverted_above must be in (0, 1]");
  if (!(o.pole_caps_below >= 0.0 && o.pole_caps_below < 1.0)) fail("pole_caps_below must be in [0, 1)");
}

}  // namespace

GpcResult run_gpc(const mesh::TriangleMesh& input, const std::string& name, const GpcOptions& options,
                  const Progress& progress) {
  check_options(options);
  const auto t_start = Clock::now();
  GpcResult result;
  GpcStats& stats = result.stats;
  // Fractions of the whole job at each stage's start (the volumetric map takes most of it).
  progress.report("validate", 0.0);

  // Unit box inside the core: centre and diagonal of the input's bounding box.
  mesh::TriangleMesh unit = input;
  if (unit.num_vertices() == 0) throw Error("mesh '" + name + "': no vertices");
  const Eigen::RowVector3d lo = unit.positions.colwise().minCoeff(), hi = unit.positions.colwise().maxCoeff();
  const Eigen::RowVector3d centre = 0.5 * (lo + hi);
  const double diagonal = (hi - lo).norm();
  if (!(diagonal > 0.0) || !std::isfinite(diagonal))
    throw Error("mesh '" + name + "': its bounding box has no finite, positive size");
  unit.positions = (unit.positions.rowwise() - centre) / diagonal;
  SolidMesh validated = validate_solid_mesh(unit, name, "gpc");
  stats.genus = validated.report.genus;
  // Shared with an uncut solid's one cuboid, whose layout and surface map use the same halfedges.
  const auto solid_mesh = std::make_shared<const mesh::HalfedgeMesh>(std::move(validated.mesh));
  if (!options.corners.empty() && stats.genus != 0)
    throw Error("gpc: corners are only accepted for a genus-0 solid (one cuboid); mesh '" + name + "' has genus " +
                std::to_string(stats.genus));
  stats.times_s["validate"] = seconds_since(t_start);

  auto t0 = Clock::now();
  progress.report("decompose", 0.02);
  // Decomposition, T-to-cube and meridian certificate with the given limb persistence (0: two
  // poles). A genus-0 solid without limbs is not cut: the blob is one cuboid on the unrefined
  // surface, as mesh2spline maps it.
  polycube::SolidDecomposition decomposition;
  std::string stage_prefix;  // names a fallback construction's stages in the progress
  polycube::TShapeLayoutOptions t_shape;
  // The decomposition the last construction was built from (after any refinement and flips),
  // so that a retry can lay it out again without decomposing anew.
  std::shared_ptr<const polycube::SolidDecomposition> prebuilt;
  // Meridian certificate of every cut of `decomposition`, with the construction's discs.
  auto certify_cuts = [&] {
    if (decomposition.loops.empty()) return;
    std::vector<std::vector<int>> loop_ids;
    for (const polycube::CutLoop& l : decomposition.loops) loop_ids.push_back(l.vertices);
    const polycube::DiscEmbedding embedding =
        polycube::check_interface_discs(decomposition.mesh, result.construction.discs, loop_ids);
    stats.cut_disc_intersections = embedding.num_intersections;
    stats.cut_discs_outside = embedding.num_outside;
    stats.cut_disc_problem = embedding.first_problem;
    stats.cut_disc_crossings = embedding.crossings;
    for (std::size_t k = 0; k < embedding.winding.size(); ++k)
      if (embedding.winding[k] < 0.5)
        throw polycube::DecompositionError("meridian check: the interface disc of cut " + std::to_string(k) +
                                           " lies outside the solid (winding number " +
                                           std::to_string(embedding.winding[k]) + " at its centre)");
  };
  bool pole_caps = false;  // the next construction keeps the poles' pieces as caps
  double pole_offset = 0.0;  // the next construction's poles, off the diameter's ends (kOffAxisPoleOffsets)
  auto construct = [&](double limb_persistence, bool tighten_caps) {
    polycube::DecompositionOptions d;
    d.snap = options.snap;
    d.cuts = options.cuts;
    d.tighten_caps = tighten_caps;
    d.morse.limb_persistence = limb_persistence;
    d.pole_caps = pole_caps;
    d.morse.pole_offset = pole_offset;
    decomposition = polycube::SolidDecomposition{};
    // A genus-0 solid is cut only if it has a limb (its poles alone cost two graph sweeps, where
    // the decomposition's harmonic solve and level sets grow faster than the mesh).
    if (stats.genus > 0 ||
        (limb_persistence > 0.0 && !polycube::morse_poles(*solid_mesh, limb_persistence).limb_tips.empty()))
      decomposition = polycube::decompose_solid(*solid_mesh, stats.genus, d);
    if (decomposition.pieces.size() <= 1 && stats.genus == 0) {
      decomposition = polycube::SolidDecomposition{};
      decomposition.mesh = solid_mesh->to_triangle_mesh();
      decomposition.halfedges = solid_mesh;
      decomposition.value.assign(decomposition.mesh.num_vertices(), 0.0);
      decomposition.parent_face.resize(decomposition.mesh.num_faces());
      std::iota(decomposition.parent_face.begin(), decomposition.parent_face.end(), 0);
      polycube::SolidPiece piece;
      piece.faces = decomposition.parent_face;
      decomposition.pieces.push_back(piece);
    }
    stats.num_saddles = decomposition.num_saddles;
    stats.tightened_cuts = decomposition.num_tightened_cuts;
    stats.flipped_cuts = 0;
    stats.cut_length_rel = polycube::cut_length(decomposition);
    stats.times_s["decompose"] = seconds_since(t0);
    progress.report(stage_prefix + "T-to-cube", 0.05);
    // Where a layout cannot be traced, a piece too coarse for its layout's disjoint paths is
    // refined (at most twice) and retried; where that fails too, the cuts are made shorter (a
    // sliver T-shape between two cuts running side by side: flip_cuts, on the decomposition as
    // it was before build_gpc and the refinement changed it) and all of it is tried again.
    const bool cut = !decomposition.loops.empty();
    std::optional<polycube::SolidDecomposition> unflipped;
    if (cut) unflipped = decomposition;
    for (int attempt = 0;; ++attempt) {
      try {
        // Only a cut solid has T-shapes, which the retry lays out again.
        auto before = cut ? std::make_shared<const polycube::SolidDecomposition>(decomposition) : nullptr;
        result.construction = polycube::build_gpc(decomposition, 1.0, options.corners, options.merge_cuboids, t_shape);
        prebuilt = std::move(before);
        break;
      } catch (const polycube::DecompositionError& e) {
        // Refining helps narrow T-shapes; past 200,000 faces it only costs time.
        if (attempt < 2 && cut && e.refinable() && decomposition.mesh.num_faces() <= 200000) {
          polycube::subdivide_decomposition(decomposition);
          continue;
        }
        // A cap's layout (not refinable) has no cut between two T-shapes to flip.
        if (!unflipped || !e.refinable()) throw;
        polycube::SolidDecomposition flipped = std::move(*unflipped);
        unflipped.reset();
        progress.report(stage_prefix + "T-to-cube: shorter cuts", 0.06);
        polycube::CutFlipOptions flips;
        flips.snap = options.snap;
        const int num_flipped = polycube::flip_cuts(flipped, flips).num_flipped;
        if (num_flipped == 0) throw;
        decomposition = std::move(flipped);
        stats.flipped_cuts = num_flipped;
        stats.cut_length_rel = polycube::cut_length(decomposition);
        attempt = -1;
      }
    }
    certify_cuts();
  };
  // The map's phases are the rest of the job (the T-to-cube stages took the first 15 %). A
  // fallback construction maps again from 15 %, its stages named so that the bar says why.
  const Progress map_progress([&](const std::string& stage, double fraction) {
    progress.report(stage_prefix + stage, 0.15 + 0.85 * fraction);
    return true;
  });
  // The choice between constructions below (limb fallback, finer limbs) compares their hex meshes'
  // folds after the sliding untangling; where the solid has limb tips at a persistence the job may
  // try, its maps keep that untangling whatever grid.face_sliding asks, so the choice stays the same.
  param::GpcGridOptions grid = options.grid;
  if (grid.face_sliding == param::GpcGridOptions::FaceSliding::Off && options.corners.empty()) {
    const double first = options.limb_persistence >= 0.0 ? options.limb_persistence : kDefaultLimbPersistence;
    const std::size_t tips = first > 0.0 ? polycube::morse_poles(*solid_mesh, first).limb_tips.size() : 0;
    const bool finer = options.limb_persistence < 0.0 &&
                       polycube::morse_poles(*solid_mesh, kFinerLimbPersistence).limb_tips.size() > tips;
    if (tips > 0 || finer) grid.face_sliding = param::GpcGridOptions::FaceSliding::On;
  }
  auto map_volume = [&] {
    t0 = Clock::now();
    progress.report(stage_prefix + "volumetric map", 0.15);
    result.map = param::compute_gpc_volumetric_map(result.construction, 1.0, grid, map_progress);
    stats.times_s["volumetric_map"] += seconds_since(t0);
  };
  auto two_pole_at = [&] {
    t0 = Clock::now();
    construct(0.0, false);
    stats.times_s["t_to_cube"] += seconds_since(t0);
    map_volume();
  };
  // §3.3.1 assumes simple saddles at distinct levels and level-set cuts that are meridians. A
  // solid symmetric about its graph diameter (a cube drilled along its three axes: poles at
  // opposite corners, a 3-fold axis) has saddles at one level and degenerate ones on the axis,
  // and a frame's bars lying along a level give cuts that no re-split turns into meridians.
  // Where the two-pole construction of a genus > 0 solid fails so, the poles move off the
  // diameter's ends (kOffAxisPoleOffsets, in turn) and all of it is tried again; the last error
  // is thrown if none works.
  // `failed`: the error of an identical two-pole construction that already ran (the limb one
  // without limb tips, caps at their levels), so that it is not built again; null if none ran.
  auto two_pole = [&](const std::string* failed) {
    std::string why;
    if (failed) {
      why = *failed;
    } else {
      try {
        two_pole_at();
        return;
      } catch (const polycube::DecompositionError& e) {
        if (stats.genus == 0 || pole_offset > 0.0) throw;
        why = e.what();
      }
    }
    const std::string prefix = stage_prefix;
    for (std::size_t i = 0; i < kOffAxisPoleOffsets.size(); ++i) {
      pole_offset = kOffAxisPoleOffsets[i];
      std::ostringstream name;
      name << "poles off the axis (" << pole_offset << "): ";
      stage_prefix = name.str();
      try {
        two_pole_at();
      } catch (const polycube::DecompositionError&) {
        if (i + 1 == kOffAxisPoleOffsets.size()) throw;
        continue;
      }
      break;
    }
    stage_prefix = prefix;
    std::ostringstream o;
    o << "pole offset " << pole_offset << " (at the diameter's ends: " << why << ")";
    stats.off_axis_poles = o.str();
  };
  // One construction's outcome, set aside while another is tried (times stay with the job).
  struct Built {
    GpcStats stats;
    polycube::GpcConstruction construction;
    param::GpcVolumetricMap map;
    polycube::SolidDecomposition decomposition;
    std::shared_ptr<const polycube::SolidDecomposition> prebuilt;
  };
  auto set_aside = [&] {
    return Built{stats, std::move(result.construction), std::move(result.map), std::move(decomposition), prebuilt};
  };
  auto restore = [&](Built& b) {
    const std::map<std::string, double> times = stats.times_s;
    result.construction = std::move(b.construction);
    result.map = std::move(b.map);
    decomposition = std::move(b.decomposition);
    prebuilt = b.prebuilt;
    stats = b.stats;
    stats.times_s = times;
  };
  // Fewer inverted hexes, then a higher least scaled Jacobian; a tie keeps the first.
  auto better = [](const param::GpcVolumetricMap& a, const param::GpcVolumetricMap& b) {
    return a.grid_inverted_hexes < b.grid_inverted_hexes ||
           (a.grid_inverted_hexes == b.grid_inverted_hexes && a.grid_min_scaled_jacobian > b.grid_min_scaled_jacobian);
  };
  // The limb construction: caps' cuts tightened first; where that fails, at their levels. Throws
  // the last DecompositionError if both fail.
  auto limbs = [&](double persistence) {
    for (const bool tighten_caps : {true, false}) {
      try {
        t0 = Clock::now();
        construct(persistence, tighten_caps);
        stats.limb_caps = static_cast<int>(result.construction.domain.caps);
        stats.limb_persistence = stats.limb_caps > 0 ? persistence : 0.0;
        stats.times_s["t_to_cube"] += seconds_since(t0);
        map_volume();
        stats.limb_fallback.clear();
        return;
      } catch (const polycube::DecompositionError& e) {
        stats.limb_fallback = e.what();
        stats.limb_caps = 0;
        stats.limb_persistence = 0.0;
        if (!tighten_caps) throw;
        stage_prefix = stage_prefix.empty() ? "limbs, caps at their levels: " : stage_prefix + "caps at their levels: ";
      }
    }
  };
  const bool untangled = options.grid.untangle != param::GpcGridOptions::Untangle::Off;
  // Limbs first (their ends become caps); where that construction fails, or its hex mesh keeps
  // more folds than the two-pole one's, the two-pole one (a genus-0 solid: one cuboid).
  const double limb_persistence = options.limb_persistence >= 0.0 ? options.limb_persistence : kDefaultLimbPersistence;
  if (limb_persistence > 0.0 && options.corners.empty()) {
    bool built = true;
    try {
      limbs(limb_persistence);
    } catch (const polycube::DecompositionError&) {
      built = false;
    }
    if (!built) {
      stage_prefix = "two poles: ";
      // Without limb tips, the limb construction that failed last (caps at their levels) is the
      // two-pole one of a genus > 0 solid.
      const bool same = stats.genus > 0 && polycube::morse_poles(*solid_mesh, limb_persistence).limb_tips.empty();
      const std::string failed = stats.limb_fallback;
      two_pole(same ? &failed : nullptr);
    }
    const bool by_folds = stats.genus > 0 || options.one_cuboid_fallback == GpcOptions::OneCuboidFallback::ByFolds;
    if (built && by_folds && stats.limb_caps > 0 && result.map.grid_inverted_hexes > 0 && untangled) {
      // The map of a limb's cap can fold where its end is detailed (claws, fingers); the
      // two-pole construction is mapped too and the better hex mesh kept (folds left by an
      // untangler turned off say nothing of the construction).
      Built with_limbs = set_aside();
      stage_prefix = "two poles: ";
      bool mapped = true;
      try {
        two_pole(nullptr);
      } catch (const polycube::DecompositionError&) {
        mapped = false;
      }
      if (mapped && better(result.map, with_limbs.map)) {
        stats.limb_fallback = "the limb construction's hex mesh has " + std::to_string(with_limbs.map.grid_inverted_hexes) +
                              " inverted hexes, the two-pole one's " + std::to_string(result.map.grid_inverted_hexes);
        stats.limb_caps = 0;
        stats.limb_persistence = 0.0;
      } else {
        restore(with_limbs);
      }
    }
  } else {
    two_pole(nullptr);
  }
  // The automatic persistence cuts only long limbs; where the kept hex mesh still folds, a thin
  // part that is no limb at that scale (a handle, a short arm) sits inside one cuboid and its
  // map folds there. Shorter branches then become caps too (more cuboids, each nearer a box),
  // tried only if they add limb tips, and the better hex mesh kept.
  if (options.limb_persistence < 0.0 && options.corners.empty() && untangled && result.map.grid_inverted_hexes > 0 &&
      polycube::morse_poles(*solid_mesh, kFinerLimbPersistence).limb_tips.size() >
          polycube::morse_poles(*solid_mesh, kDefaultLimbPersistence).limb_tips.size()) {
    Built kept = set_aside();
    stage_prefix = "finer limbs: ";
    bool mapped = true;
    try {
      limbs(kFinerLimbPersistence);
    } catch (const polycube::DecompositionError&) {
      mapped = false;
    }
    auto describe = [](const param::GpcVolumetricMap& m) {
      std::ostringstream o;
      o << m.grid_inverted_hexes << " inverted hexes, least scaled Jacobian " << m.grid_min_scaled_jacobian;
      return o.str();
    };
    std::ostringstream tried;
    tried << "persistence " << kFinerLimbPersistence << ": "
          << (mapped ? describe(result.map) : "no construction (" + stats.limb_fallback + ")");
    if (mapped && better(result.map, kept.map)) {
      stats.finer_limbs = tried.str() + "; kept it (the first: " + describe(kept.map) + ")";
    } else {
      restore(kept);
      stats.finer_limbs = tried.str() + "; kept the first (" + describe(result.map) + ")";
    }
  }
  // §3.3.1 (limbs as caps): a limb at an end of the graph diameter (a key's shaft, a pair of
  // glasses' temples) has no limb tip: its end is a pole, whose piece the decomposition merges
  // into the tube or T-shape the limb hangs from, and that piece's surface map crowds the whole
  // limb into a spot of one face. Where no cap was kept and a surface map has such a spot (its
  // density before the squeeze rescue, which widens it but leaves the limb's cells a sliver of
  // the face), the poles' pieces become caps and the construction is mapped too. It is kept if
  // that opens the spot (kPoleCapsGain times the first's least density; a squeeze elsewhere,
  // between the holes of a plate, stays about as it was). Its hex mesh may fold more where the
  // surface is held (key: 60 inverted hexes against 1): the spline's untangling opens those,
  // while no untangling opens a squeezed map.
  auto least_density = [](const param::GpcVolumetricMap& m, bool rescued) {
    double least = std::numeric_limits<double>::infinity();
    for (const param::CuboidSurfaceMap& s : m.surface_maps)
      least = std::min(least, rescued ? s.least_density : s.unrescued_least_density);
    return least;
  };
  if (options.pole_caps_below > 0.0 && stats.genus > 0 && options.corners.empty() &&
      result.construction.domain.caps == 0 && least_density(result.map, false) < options.pole_caps_below) {
    Built kept = set_aside();
    stage_prefix = "caps at the poles: ";
    pole_caps = true;
    bool mapped = true;
    try {
      limbs(0.0);
    } catch (const polycube::DecompositionError& e) {
      mapped = false;
      stats.pole_caps = std::string("no construction (") + e.what() + ")";
    }
    pole_caps = false;
    auto describe = [&](const param::GpcVolumetricMap& m) {
      std::ostringstream o;
      o << "least surface density " << least_density(m, false) << " (" << least_density(m, true)
        << " after the squeeze rescue), " << m.grid_inverted_hexes << " inverted hexes";
      return o.str();
    };
    const std::string tried = "caps at the poles: " + (mapped ? describe(result.map) : stats.pole_caps);
    if (mapped && least_density(result.map, false) >= kPoleCapsGain * least_density(kept.map, false)) {
      stats.pole_caps = tried + "; kept it (the first: " + describe(kept.map) + ")";
    } else {
      restore(kept);
      stats.pole_caps = tried + "; kept the first (" + describe(result.map) + ")";
    }
  }
  // A T-shape's centre as tall as the crotch's height can be too flat where thin tubes meet
  // (the concave corners and the top corners near the saddle between the arms at almost one
  // height): its corner hexes stay near flat whatever the hex optimizer does. The same
  // construction with the concave corners further down the stem is then mapped too, and the
  // better hex mesh kept.
  const bool folds_or_poor =
      options.taller_centres_below > -1.0 &&
      (result.map.grid_inverted_hexes > 0 || result.map.grid_min_scaled_jacobian < options.taller_centres_below);
  const bool folds_widely = result.map.grid_inverted_hexes >
                            options.taller_centres_inverted_above * static_cast<double>(result.map.hex_mesh.hexes.size());
  if (untangled && result.construction.domain.t_shapes > 0 && (folds_or_poor || folds_widely)) {
    Built kept = set_aside();
    stage_prefix = "taller T-shape centres: ";
    t_shape.concave_corner_height = kTallerCentreHeight;
    bool mapped = true;
    try {
      t0 = Clock::now();
      progress.report(stage_prefix + "T-to-cube", 0.05);
      decomposition = *kept.prebuilt;
      result.construction =
          polycube::build_gpc(decomposition, 1.0, options.corners, options.merge_cuboids, t_shape);
      certify_cuts();
      stats.times_s["t_to_cube"] += seconds_since(t0);
      map_volume();
    } catch (const polycube::DecompositionError& e) {
      mapped = false;
      stats.taller_centres = std::string("no construction (") + e.what() + ")";
    }
    auto describe = [](const param::GpcVolumetricMap& m) {
      std::ostringstream o;
      o << m.grid_inverted_hexes << " inverted hexes, least scaled Jacobian " << m.grid_min_scaled_jacobian;
      return o.str();
    };
    std::ostringstream tried;
    tried << "concave corners at " << kTallerCentreHeight
          << " of the crotch's height: " << (mapped ? describe(result.map) : stats.taller_centres);
    if (mapped && better(result.map, kept.map)) {
      stats.taller_centres = tried.str() + "; kept it (the first: " + describe(kept.map) + ")";
    } else {
      restore(kept);
      stats.taller_centres = tried.str() + "; kept the first (" + describe(result.map) + ")";
    }
  }
  // Back to model units.
  auto to_model = [&](mesh::Positions& p) { p = (p * diagonal).rowwise() + centre; };
  to_model(decomposition.mesh.positions);
  decomposition.halfedges.reset();
  for (polycube::CuboidSurface& s : result.construction.surfaces) {
    to_model(s.mesh.positions);
    s.halfedges.reset();
  }
  for (polycube::InterfaceDisc& d : result.construction.discs) to_model(d.positions);
  for (param::GpcCuboidGrid& g : result.map.grids) to_model(g.xyz);
  to_model(result.map.hex_mesh.xyz);
  for (polycube::GpcCuboid& c : result.construction.domain.cuboids)
    for (Eigen::Vector3d& x : c.corner_xyz) x = x * diagonal + centre.transpose();
  for (polycube::GpcIllPoint& p : result.construction.domain.ill_points)
    for (Eigen::Vector3d& x : p.xyz) x = x * diagonal + centre.transpose();

  result.face_cuboid.assign(decomposition.mesh.num_faces(), -1);
  for (std::size_t c = 0; c < result.construction.surfaces.size(); ++c)
    for (int f : result.construction.surfaces[c].surface_face)
      if (f >= 0) result.face_cuboid[f] = static_cast<int>(c);
  result.surface = std::move(decomposition.mesh);

  const polycube::GpcDomain& domain = result.construction.domain;
  stats.t_shapes = domain.t_shapes;
  stats.tubes = domain.tubes;
  stats.caps = domain.caps;
  stats.cuboids = static_cast<int>(domain.cuboids.size());
  stats.ill_points = static_cast<int>(domain.ill_points.size());
  stats.interfaces = static_cast<int>(domain.interfaces.size());
  stats.flipped_triangles = result.map.flipped_triangles;
  stats.grid_inverted_hexes = result.map.grid_inverted_hexes;
  stats.grid_harmonic_inverted_hexes = result.map.harmonic_inverted_hexes;
  stats.grid_min_scaled_jacobian = result.map.grid_min_scaled_jacobian;
  stats.cuboid_grid_inverted_hexes = result.map.cuboid_grid_inverted_hexes;
  stats.cuboid_grid_min_scaled_jacobian = result.map.cuboid_grid_min_scaled_jacobian;
  for (char p : result.map.hex_mesh.padding) stats.padding_hexes += p;
  stats.interface_gap_rel = result.map.interface_gap_rel;
  const std::vector<double> ratios = polycube::face_area_ratios(result.construction);
  if (!ratios.empty()) {
    stats.face_area_ratio_min = *std::min_element(ratios.begin(), ratios.end());
    stats.face_area_ratio_max = *std::max_element(ratios.begin(), ratios.end());
  }
  stats.shared_nodes = result.map.shared_nodes;
  for (const param::GpcCuboidGrid& g : result.map.grids) stats.grid_nodes += g.nodes[0] * g.nodes[1] * g.nodes[2];
  stats.surface_vertices = result.surface.num_vertices();
  stats.times_s["total"] = seconds_since(t_start);
  progress.report("done", 1.0);
  return result;
}

}  // namespace volspline::pipeline
