// SPDX-License-Identifier: MIT
#include "core/param/gpc_volumetric_map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <string>

#include "core/common/error.h"
#include "core/linalg/conjugate_gradient.h"
#include "core/linalg/csr_matrix.h"
#include "core/param/barrier_untangling.h"
#include "core/param/cuboid_surface_locator.h"
#include "core/param/hex_grid_untangling.h"
#include "core/param/hex_min_quality.h"
#include "core/param/surface_distance.h"
#include "core/mesh/hex_quality.h"
#include "core/mesh/surface_creases.h"
#include "core/param/volumetric_grid_map.h"

namespace volspline::param {

namespace {

int find(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// The face of node (i, j, k) on each axis end, as a bit set over cube faces.
int node_faces(const std::array<int, 3>& n, const std::array<int, 3>& ijk) {
  int faces = 0;
  for (int a = 0; a < 3; ++a) {
    if (ijk[a] == 0) faces |= 1 << (2 * a);
    if (ijk[a] == n[a] - 1) faces |= 1 << (2 * a + 1);
  }
  return faces;
}

// A step's own fractions reported as [lo, hi] of the map's; cancellation passes through.
Progress share_of(const Progress& progress, double lo, double hi) {
  return Progress([&progress, lo, hi](const std::string& stage, double fraction) {
    progress.report(stage, lo + (hi - lo) * fraction);
    return true;
  });
}

// Surface triangles whose normals differ by more than this (about 75°) across an edge make a
// crease: a cube's edge (90°) is one, the noise of a scanned or coarse smooth surface is not.
constexpr double kCreaseAngleRad = 1.3;
// ... and must hold over this many mean edge lengths (mesh::SurfaceCreases' scale): a noisy
// triangulation's ripples and slivers turn normals by as much along single edges, and holding
// their nodes pins padding hexes flat.
constexpr double kCreaseScale = 3.0;
// Rounds of slide_and_raise while folds are left.
constexpr int kSlideRounds = 3;
// slide_and_raise's barrier pass: MinQualityOptions::barrier and its sweeps at most.
constexpr double kBarrierMargin = 0.5;
constexpr int kBarrierSweeps = 10;
// slide_and_raise's MinQualityOptions::min_edge: this times each node's shortest edge on entry.
constexpr double kMinEdgeShrink = 0.05;
// relax_worst_hexes: the band above the least value that seeds the region, the rings of hexes
// grown around it (a pass that fails is tried once more up to kRelaxMaxRings wide, below
// grid.wider_relax_below), and the passes at most (each kept only if it raises the least value).
constexpr double kRelaxBand = 0.02;
constexpr int kRelaxRings = 2;
constexpr int kRelaxMaxRings = 3;
constexpr int kRelaxPasses = 3;
// grid.padded_reference Better: a folded corner whose determinant against the mean cell is under
// this fraction of the untangler's first ε is one the mean cell's barrier does not see, and where
// more than kBlindShare of the folded corners are such, the mean cell's run is left out.
constexpr double kBlindDet = 1e-3;
constexpr double kBlindShare = 0.15;

// The solid's surface as one triangle soup: the surface triangles of every cuboid's mesh.
mesh::TriangleMesh whole_surface(const polycube::GpcConstruction& construction) {
  int nv = 0, nt = 0;
  for (const polycube::CuboidSurface& cs : construction.surfaces) {
    nv += cs.mesh.num_vertices();
    for (int t = 0; t < cs.mesh.num_faces(); ++t) nt += cs.surface_face[t] >= 0;
  }
  mesh::TriangleMesh whole;
  whole.positions.resize(nv, 3);
  whole.triangles.resize(nt, 3);
  int v0 = 0, t0 = 0;
  for (const polycube::CuboidSurface& cs : construction.surfaces) {
    whole.positions.middleRows(v0, cs.mesh.num_vertices()) = cs.mesh.positions;
    for (int t = 0; t < cs.mesh.num_faces(); ++t)
      if (cs.surface_face[t] >= 0) whole.triangles.row(t0++) = cs.mesh.triangles.row(t).array() + v0;
    v0 += cs.mesh.num_vertices();
  }
  return whole;
}

// Per node of pm: 1 if it belongs to a hex whose least corner scaled Jacobian is below `bound`.
std::vector<char> nodes_of_hexes_below(const HexMesh& pm, double bound) {
  std::vector<char> marked(pm.xyz.rows(), 0);
  for (const auto& hex : pm.hexes) {
    std::array<Eigen::Vector3d, 8> x;
    for (int q = 0; q < 8; ++q) x[q] = pm.xyz.row(hex[q]).transpose();
    if (mesh::hex_min_scaled_jacobian(x) < bound)
      for (int v : hex) marked[v] = 1;
  }
  return marked;
}

// The node marks grown by one ring of hexes: every node of a hex with a marked node.
std::vector<char> grown_by_hexes(const std::vector<std::array<int, 8>>& hexes, const std::vector<char>& marked) {
  std::vector<char> next = marked;
  for (const auto& hex : hexes) {
    bool any = false;
    for (int v : hex) any = any || marked[v];
    if (any)
      for (int v : hex) next[v] = 1;
  }
  return next;
}

// True if more than kBlindShare of the folded corners that touch a node not held have a determinant,
// against a cube of the mean corner volume (untangle_hex_mesh's MeanCell), under kBlindDet of the
// first ε of its continuation (Garanzha et al. 2021, §3: from the least such determinant). The
// barrier χ(D, ε) is then nearly flat in D at those corners: the mean cell cannot see their sign.
bool mean_cell_blind(const HexMesh& pm, const std::vector<char>& held) {
  auto corner_det = [&](const std::array<int, 8>& hex, int c) {
    Eigen::Matrix3d e;
    for (int a = 0; a < 3; ++a)
      e.col(a) = ((c >> a & 1) ? -1.0 : 1.0) * (pm.xyz.row(hex[c ^ (1 << a)]) - pm.xyz.row(hex[c])).transpose();
    return e.determinant();
  };
  const double corners = 8.0 * static_cast<double>(pm.hexes.size());
  double mean_det = 0.0;
  for (const auto& hex : pm.hexes)
    for (int c = 0; c < 8; ++c) mean_det += corner_det(hex, c) / corners;
  const double volume = std::max(mean_det, 1e-300);
  std::vector<double> folded;
  double least = std::numeric_limits<double>::infinity();
  for (const auto& hex : pm.hexes)
    for (int c = 0; c < 8; ++c) {
      bool movable = !held[hex[c]];
      for (int a = 0; a < 3; ++a) movable = movable || !held[hex[c ^ (1 << a)]];
      if (!movable) continue;
      const double d = corner_det(hex, c) / volume;
      least = std::min(least, d);
      if (d <= 0.0) folded.push_back(-d);
    }
  if (folded.empty()) return false;
  const double eps = first_barrier_eps(least);
  const auto blind = std::count_if(folded.begin(), folded.end(), [&](double d) { return d < kBlindDet * eps; });
  return static_cast<double>(blind) > kBlindShare * static_cast<double>(folded.size());
}

// untangle_hex_mesh (one round) with each hex's reference cell the mean cell, and where that leaves
// as many folds as it found, again from the same start with each hex's own cell
// (HexGridUntangleOptions::Reference): the padded mesh's hexes differ in size by orders of
// magnitude, and a fold in a small hex that the mean-cell barrier does not see opens with its own.
// The result with fewer folds stays (the mean cell's on a tie). Returns the nodes moved.
int untangle_either_reference(HexMesh& pm, const std::vector<char>& fixed, const SlidingNodes& sliding,
                              const Progress& progress) {
  const int folded = hex_mesh_quality(pm).num_inverted;
  const mesh::Positions start = pm.xyz;
  HexGridUntangleOptions untangle;
  untangle.rounds = 1;
  const int moved = untangle_hex_mesh(pm.hexes, fixed, pm.xyz, {}, untangle, &sliding, share_of(progress, 0.0, 0.5)).free_nodes;
  const int mean_folded = hex_mesh_quality(pm).num_inverted;
  if (mean_folded < folded) return moved;
  const mesh::Positions mean_result = pm.xyz;
  pm.xyz = start;
  untangle.reference = HexGridUntangleOptions::Reference::OwnCell;
  const int own_moved =
      untangle_hex_mesh(pm.hexes, fixed, pm.xyz, {}, untangle, &sliding, share_of(progress, 0.5, 1.0)).free_nodes;
  if (hex_mesh_quality(pm).num_inverted < mean_folded) return own_moved;
  pm.xyz = mean_result;
  return moved;
}

// The hexes within kRelaxBand of the least scaled Jacobian (and kRelaxBand short of the target)
// and `rings` rings of hexes around them relaxed together (improve_hex_mesh on those hexes
// alone, the rest held: its reference cell is their own mean), then the least value raised again
// over the whole mesh; kept if it rose without a fold. The greedy raise moves one node at a time and
// stops where the worst corner needs several nodes to move together (a T-shape's junction, a
// thin strip of a surface face); the barrier energy moves the whole neighbourhood at once.
// Returns true if kept; *least: pm's least scaled Jacobian on return.
bool relax_worst_hexes(const std::vector<char>& fixed, const SlidingNodes& sliding, const GpcGridOptions& options,
                       const MinQualityOptions& quality, int rings, HexMesh& pm, double* least) {
  const HexMeshQuality start = hex_mesh_quality(pm);
  *least = start.min_scaled_jacobian;
  // Hexes just below the target are where the raise stops by design, not a spot to relax.
  const double seed_bound = std::min(start.min_scaled_jacobian + kRelaxBand, options.min_quality_target - kRelaxBand);
  if (start.num_inverted > 0 || !(start.min_scaled_jacobian < seed_bound)) return false;
  std::vector<char> region = nodes_of_hexes_below(pm, seed_bound);
  for (int ring = 0; ring < rings; ++ring) region = grown_by_hexes(pm.hexes, region);
  std::vector<std::array<int, 8>> local;
  for (const auto& hex : pm.hexes)
    if (std::any_of(hex.begin(), hex.end(), [&](int v) { return region[v] != 0; })) local.push_back(hex);
  std::vector<char> held = fixed;
  for (std::size_t r = 0; r < held.size(); ++r) held[r] = held[r] || !region[r];
  const mesh::Positions before = pm.xyz;
  improve_hex_mesh(local, held, pm.xyz, options.quality_iterations, 0.5, &sliding);
  raise_min_scaled_jacobian(pm.hexes, fixed, pm.xyz, quality, &sliding);
  const HexMeshQuality after = hex_mesh_quality(pm);
  if (after.num_inverted == 0 && after.min_scaled_jacobian > start.min_scaled_jacobian) {
    *least = after.min_scaled_jacobian;
    return true;
  }
  pm.xyz = before;
  return false;
}

// The last stage of the padded mesh: every surface node slides on the whole surface, poly-edge
// and corner nodes too, unless the surface has a crease there. A poly-edge is a line of the
// parameterization, not of the smooth surface, and a padding hex whose surface quad has a
// poly-edge side is only as good as the angles that side makes. The least scaled Jacobian is
// raised (raise_min_scaled_jacobian); folds it leaves are untangled once more with this sliding
// and the least value raised again, for a few rounds (untangling first would undo what the
// first raise can reach).
// unused: rows of pm that are no node. Returns the nodes the untangler moved.
int slide_and_raise(const polycube::GpcConstruction& construction, const std::vector<char>& unused,
                    const GpcGridOptions& options, HexMesh& pm, const Progress& progress) {
  const int rows = static_cast<int>(pm.xyz.rows());
  const mesh::TriangleMesh whole = whole_surface(construction);
  const SurfaceDistance surface(whole);
  const mesh::SurfaceCreases creases(whole, kCreaseAngleRad, kCreaseScale);
  std::vector<int> near_face(rows, -1);
  std::vector<char> fixed(rows);
  SlidingNodes sliding;
  sliding.slides.assign(rows, 0);
  for (int r = 0; r < rows; ++r) {
    if (pm.on_surface[r] && !unused[r]) surface.closest_point(pm.xyz.row(r).transpose(), nullptr, &near_face[r]);
    fixed[r] = unused[r] || (pm.on_surface[r] && creases.triangle_near_crease(near_face[r]));
    sliding.slides[r] = !fixed[r] && pm.on_surface[r];
  }
  // Each node's last triangle and the triangles around it spare most searches (the optimizers
  // move it a little).
  std::vector<SurfaceDistance::Nearby> nearby(rows);
  sliding.project = [&](int r, const Eigen::Vector3d& p, Eigen::Matrix3d* tangent) {
    Eigen::Vector3d normal;
    const Eigen::Vector3d q = surface.closest_point(p, &normal, &near_face[r], &nearby[r]);
    if (tangent) *tangent = Eigen::Matrix3d::Identity() - normal * normal.transpose();
    return q;
  };
  MinQualityOptions quality;
  quality.target = options.min_quality_target;
  quality.max_sweeps = options.min_quality_sweeps;
  // One stretch bound for all the stage's calls: 10 times each node's longest edge on entry, a
  // safety net against a node walking away (most moves stay far below it).
  quality.max_edge = longest_hex_edges(pm.hexes, pm.xyz);
  for (double& l : quality.max_edge) l *= 10.0;
  // And a floor on each node's shortest edge: a twentieth of its entry value.
  quality.min_edge = shortest_hex_edges(pm.hexes, pm.xyz);
  for (double& l : quality.min_edge) l *= kMinEdgeShrink;
  // Rounds of raise, then untangle what stays folded (kept if no worse), then raise again.
  int untangled = 0;
  bool spread = false;  // the barrier pass has been tried
  // The best state after a raise (fewest folds, then the highest least value): the rounds'
  // untanglings may end on a worse path, and the stage ends no worse than its best round.
  HexMeshQuality best_quality{std::numeric_limits<int>::max(), -2.0};
  mesh::Positions best;
  auto keep_if_best = [&] {
    const HexMeshQuality q = hex_mesh_quality(pm);
    if (q.num_inverted < best_quality.num_inverted ||
        (q.num_inverted == best_quality.num_inverted && q.min_scaled_jacobian > best_quality.min_scaled_jacobian)) {
      best_quality = q;
      best = pm.xyz;
    }
  };
  for (int round = 0; round < kSlideRounds; ++round) {
    const double lo = double(round) / kSlideRounds, hi = double(round + 1) / kSlideRounds;
    if (!spread && hex_mesh_quality(pm).num_inverted == 0) {
      // The first round without folds: the greedy raise alone, and a barrier pass followed by
      // the greedy raise; the better of the two stays. The greedy ascent stops in local optima
      // that depend on round-off (on the eight they differ between rotations of one layout); the
      // barrier first moves all the poor hexes together.
      spread = true;
      const mesh::Positions start = pm.xyz;
      raise_min_scaled_jacobian(pm.hexes, fixed, pm.xyz, quality, &sliding, share_of(progress, lo, lo + 0.3 * (hi - lo)));
      const mesh::Positions greedy = pm.xyz;
      const HexMeshQuality greedy_quality = hex_mesh_quality(pm);
      pm.xyz = start;
      MinQualityOptions barrier = quality;
      barrier.barrier = kBarrierMargin;
      barrier.max_sweeps = std::min(quality.max_sweeps, kBarrierSweeps);
      raise_min_scaled_jacobian(pm.hexes, fixed, pm.xyz, barrier, &sliding, share_of(progress, lo + 0.3 * (hi - lo), lo + 0.4 * (hi - lo)));
      raise_min_scaled_jacobian(pm.hexes, fixed, pm.xyz, quality, &sliding, share_of(progress, lo + 0.4 * (hi - lo), lo + 0.7 * (hi - lo)));
      const HexMeshQuality spread_quality = hex_mesh_quality(pm);
      if (spread_quality.num_inverted > 0 || !(spread_quality.min_scaled_jacobian > greedy_quality.min_scaled_jacobian))
        pm.xyz = greedy;
    } else {
      raise_min_scaled_jacobian(pm.hexes, fixed, pm.xyz, quality, &sliding, share_of(progress, lo, lo + 0.7 * (hi - lo)));
    }
    keep_if_best();
    const int folded = hex_mesh_quality(pm).num_inverted;
    if (folded == 0) break;
    const mesh::Positions before = pm.xyz;
    untangled += untangle_either_reference(pm, fixed, sliding, share_of(progress, lo + 0.7 * (hi - lo), hi));
    if (hex_mesh_quality(pm).num_inverted > folded) pm.xyz = before;
    if (round + 1 == kSlideRounds) {
      raise_min_scaled_jacobian(pm.hexes, fixed, pm.xyz, quality, &sliding, share_of(progress, 1.0, 1.0));
      keep_if_best();
    }
  }
  pm.xyz = best;
  // A region too narrow holds the worst corner's neighbours where they are: where the relaxation
  // fails, the next try grows one ring wider (and later passes keep that width) while the mesh is
  // below grid.wider_relax_below: above it the mesh meets the quality the job aims at, and the try
  // costs a raise over the whole mesh.
  for (int pass = 0, rings = kRelaxRings; pass < kRelaxPasses;) {
    double least = 0.0;
    if (relax_worst_hexes(fixed, sliding, options, quality, rings, pm, &least))
      ++pass;
    else if (++rings > kRelaxMaxRings || !(least < options.wider_relax_below))
      break;
  }
  // Folds left where crease nodes are held: a surface quad with three held nodes in a row (a
  // claw's ridge) has a flat corner whatever the free nodes do. Around the folded hexes (two
  // rings) those nodes slide too, for one more untangle and raise, kept if it leaves fewer folds
  // (or as many and a higher least value). A mesh without folds is not touched.
  const HexMeshQuality left = hex_mesh_quality(pm);
  if (left.num_inverted > 0) {
    std::vector<char> near = nodes_of_hexes_below(pm, std::nextafter(0.0, 1.0));
    for (int ring = 0; ring < 2; ++ring) near = grown_by_hexes(pm.hexes, near);
    std::vector<char> released = fixed;
    SlidingNodes wider = sliding;
    for (int r = 0; r < rows; ++r)
      if (near[r] && fixed[r] && !unused[r] && pm.on_surface[r]) {
        released[r] = 0;
        wider.slides[r] = 1;
      }
    const mesh::Positions before = pm.xyz;
    const int moved = untangle_either_reference(pm, released, wider, share_of(progress, 1.0, 1.0));
    raise_min_scaled_jacobian(pm.hexes, released, pm.xyz, quality, &wider, share_of(progress, 1.0, 1.0));
    const HexMeshQuality after = hex_mesh_quality(pm);
    if (after.num_inverted < left.num_inverted ||
        (after.num_inverted == left.num_inverted && after.min_scaled_jacobian > left.min_scaled_jacobian))
      untangled += moved;
    else
      pm.xyz = before;
  }
  return untangled;
}

// The padded hex mesh pm untangled with only the surface held, the nodes inside an exposed cube
// face sliding on it, improved around its poor hexes, then slide_and_raise. root, offset, total: the grid node
// identification of compute_gpc_volumetric_map (rows of pm below total that are not roots are
// unused). Returns the nodes the untanglers moved. progress: the untanglers' steps and the quality sweeps.
int untangle_padded_mesh(const polycube::GpcConstruction& construction, const std::vector<int>& root,
                         const std::vector<int>& offset, int total, const GpcGridOptions& options, HexMesh& pm,
                         const Progress& progress) {
  const polycube::GpcDomain& domain = construction.domain;
  const int nc = static_cast<int>(domain.cuboids.size());
  int untangled = 0;
  const int rows = static_cast<int>(pm.xyz.rows());
  // Surface nodes inside one exposed cube face slide on the surface (the padding hex of a
  // bad surface quad folds whatever its inner nodes do); nodes on poly-edges, cut loops and
  // corners stay where the surface maps put them.
  // slides[r]: 1 + the patch (cuboid·6 + face) the node r projects onto, 0 if it does not slide.
  std::vector<int> slides(rows, 0);
  for (int c = 0; c < nc; ++c) {
    const auto& n = domain.cuboids[c].nodes;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          const int faces = node_faces(n, {i, j, k});
          if (faces == 0 || (faces & (faces - 1)) != 0) continue;
          int f = 0;
          while (!(faces >> f & 1)) ++f;
          if (domain.cuboids[c].face_interface[f] < 0)
            slides[root[offset[c] + grid_node_index(n, i, j, k)]] = 1 + 6 * c + f;
        }
  }
  std::vector<char> fixed(rows);
  for (int r = 0; r < rows; ++r) fixed[r] = (pm.on_surface[r] && !slides[r]) || (r < total && root[r] != r);
  // Each patch on its own: a node near a thin part must not land on the far side.
  std::vector<std::unique_ptr<SurfaceDistance>> patches(6 * nc);
  for (int c = 0; c < nc; ++c) {
    const polycube::CuboidSurface& cs = construction.surfaces[c];
    for (int f = 0; f < 6; ++f) {
      if (domain.cuboids[c].face_interface[f] >= 0) continue;
      mesh::TriangleMesh patch;
      patch.positions = cs.mesh.positions;
      std::vector<int> keep;
      for (int t = 0; t < cs.mesh.num_faces(); ++t)
        if (cs.surface_face[t] >= 0 && cs.layout.face_region[t] == f) keep.push_back(t);
      if (keep.empty()) continue;
      patch.triangles.resize(static_cast<int>(keep.size()), 3);
      for (std::size_t t = 0; t < keep.size(); ++t) patch.triangles.row(t) = cs.mesh.triangles.row(keep[t]);
      patches[6 * c + f] = std::make_unique<SurfaceDistance>(patch);
    }
  }
  for (int r = 0; r < rows; ++r)
    if (slides[r] && !patches[slides[r] - 1]) slides[r] = 0, fixed[r] = 1;
  // settle: first with the whole surface held; then the folds left, with the face nodes sliding
  // (grid.face_sliding); then improved around the poor hexes if fold-free. Run with the reference cells that
  // grid.padded_reference asks for, each from the same start.
  std::vector<char> held(rows);
  for (int r = 0; r < rows; ++r) held[r] = fixed[r] || pm.on_surface[r];
  SlidingNodes sliding;
  sliding.slides.resize(rows);
  for (int r = 0; r < rows; ++r) sliding.slides[r] = slides[r] > 0;
  // Each sliding node's last triangle and the triangles around it spare most searches (the
  // optimizer moves it a little).
  std::vector<int> last_face(rows, -1);
  std::vector<SurfaceDistance::Nearby> nearby(rows);
  sliding.project = [&](int r, const Eigen::Vector3d& p, Eigen::Matrix3d* tangent) {
    Eigen::Vector3d normal;
    const Eigen::Vector3d q = patches[slides[r] - 1]->closest_point(p, &normal, &last_face[r], &nearby[r]);
    if (tangent) *tangent = Eigen::Matrix3d::Identity() - normal * normal.transpose();
    return q;
  };
  // settle_or_give_up: stop after the held untangling if it leaves more folded corners than it
  // found (the reference cell's barrier does not see the folds), for a run that another
  // reference's run will be compared with.
  auto settle = [&](HexGridUntangleOptions::Reference reference, const Progress& share, bool settle_or_give_up) {
    int moved = 0;
    HexGridUntangleOptions held_options;
    held_options.rounds = 1;
    held_options.reference = reference;
    const HexGridUntangleReport held_report =
        untangle_hex_mesh(pm.hexes, held, pm.xyz, {}, held_options, nullptr, share_of(share, 0.0, 0.5));
    moved += held_report.free_nodes;
    if (settle_or_give_up && held_report.final_inverted > held_report.initial_inverted) return moved;
    const int held_count = hex_mesh_quality(pm).num_inverted;
    if (held_count > 0 && options.face_sliding == GpcGridOptions::FaceSliding::On) {
      const mesh::Positions held_result = pm.xyz;
      HexGridUntangleOptions slide_options = held_options;
      moved += untangle_hex_mesh(pm.hexes, fixed, pm.xyz, {}, slide_options, &sliding, share_of(share, 0.5, 1.0)).free_nodes;
      if (hex_mesh_quality(pm).num_inverted > held_count) pm.xyz = held_result;
    }
    const HexMeshQuality untangled_quality = hex_mesh_quality(pm);
    if (options.quality_iterations > 0 && untangled_quality.num_inverted == 0) {
      // Only around the poor hexes: nodes within 1 ring of a hex below scaled Jacobian 0.3.
      const std::vector<char> region = nodes_of_hexes_below(pm, 0.3);
      const std::vector<char> next = grown_by_hexes(pm.hexes, region);
      // Without face sliding the surface stays held here too (as in the held untangling): a fit
      // that samples each node at its grid parameter (mesh2spline) would read a node moved along
      // the surface as a second surface map disagreeing with the vertices' one.
      const std::vector<char>& kept = options.face_sliding == GpcGridOptions::FaceSliding::Off ? held : fixed;
      std::vector<char> frozen(rows);
      for (int r = 0; r < rows; ++r) frozen[r] = kept[r] || !next[r];
      // The energy is a sum over corners: kept only if the worst corner did not get worse.
      const mesh::Positions before = pm.xyz;
      improve_hex_mesh(pm.hexes, frozen, pm.xyz, options.quality_iterations, 0.5, &sliding);
      const HexMeshQuality improved = hex_mesh_quality(pm);
      if (improved.num_inverted > 0 || improved.min_scaled_jacobian < untangled_quality.min_scaled_jacobian)
        pm.xyz = before;
    }
    return moved;
  };
  auto raise_stage = [&] {
    if (options.min_quality_sweeps == 0) return 0;
    std::vector<char> unused(rows, 0);
    for (int r = 0; r < total; ++r) unused[r] = root[r] != r;
    return slide_and_raise(construction, unused, options, pm, share_of(progress, 0.6, 1.0));
  };
  using Reference = HexGridUntangleOptions::Reference;
  if (options.padded_reference != GpcGridOptions::PaddedReference::Better) {
    untangled += settle(options.padded_reference == GpcGridOptions::PaddedReference::OwnCell ? Reference::OwnCell
                                                                                            : Reference::MeanCell,
                        share_of(progress, 0.0, 0.6), false);
  } else if (mean_cell_blind(pm, held)) {
    // The mean cell's held untangling would add folds and give up: the own cell's run alone.
    untangled += settle(Reference::OwnCell, share_of(progress, 0.0, 0.6), false);
  } else {
    // The mean cell's run gives up where its held untangling adds folds (on armadillo it more
    // than doubles them, and the sliding untangling that would follow is half the job's time
    // for a result the own cell's beats); the own cell's run then decides as below.
    const mesh::Positions start = pm.xyz;
    const int mean_moved = settle(Reference::MeanCell, share_of(progress, 0.0, 0.3), true);
    const HexMeshQuality mean_quality = hex_mesh_quality(pm);
    untangled += mean_moved;
    if (mean_quality.num_inverted > 0) {
      const mesh::Positions mean_result = pm.xyz;
      pm.xyz = start;
      std::fill(last_face.begin(), last_face.end(), -1);
      std::fill(nearby.begin(), nearby.end(), SurfaceDistance::Nearby{});
      const int own_moved = settle(Reference::OwnCell, share_of(progress, 0.3, 0.6), false);
      const HexMeshQuality own_quality = hex_mesh_quality(pm);
      if (own_quality.num_inverted < mean_quality.num_inverted)
        untangled += own_moved - mean_moved;
      else
        pm.xyz = mean_result;
    }
  }
  return untangled + raise_stage();
}

}  // namespace

GpcVolumetricMap compute_gpc_volumetric_map(polycube::GpcConstruction& construction, double bbox_diagonal,
                                            const GpcGridOptions& options, const Progress& progress) {
  polycube::GpcDomain& domain = construction.domain;
  const int nc = static_cast<int>(domain.cuboids.size());
  GpcVolumetricMap out;

  // Node counts: one spacing h for all cuboids; equal sizes (glued axes) give equal counts.
  double volume = 0.0;
  for (const polycube::GpcCuboid& c : domain.cuboids) volume += c.size[0] * c.size[1] * c.size[2];
  const double h = std::cbrt(volume / std::max(options.target_nodes, 64));
  for (polycube::GpcCuboid& c : domain.cuboids)
    for (int a = 0; a < 3; ++a)
      c.nodes[a] = std::clamp(static_cast<int>(std::lround(c.size[a] / h)) + 1, options.min_nodes, options.max_nodes);

  // §3.4.1: surface maps and their inverse lookups.
  std::vector<CuboidSurfaceLocator> locators;
  locators.reserve(nc);
  for (int c = 0; c < nc; ++c) {
    progress.report("surface map", 0.3 * c / nc);
    const polycube::CuboidSurface& s = construction.surfaces[c];
    const std::shared_ptr<const mesh::HalfedgeMesh> built =
        s.halfedges ? s.halfedges
                    : std::make_shared<const mesh::HalfedgeMesh>(
                          mesh::HalfedgeMesh::build(s.mesh, "gpc cuboid " + std::to_string(c)));
    const mesh::HalfedgeMesh& hm = *built;
    CuboidSurfaceMapOptions map_options;
    map_options.area_balance_iterations = options.area_balance_iterations;
    map_options.squeezed_below = options.squeezed_below;
    try {
      out.surface_maps.push_back(compute_cuboid_surface_map(hm, s.layout, map_options));
    } catch (const Error& e) {
      throw polycube::DecompositionError("surface map of cuboid " + std::to_string(c) + ": " + e.what());
    }
    out.flipped_triangles += out.surface_maps.back().num_flipped;
    locators.emplace_back(hm, out.surface_maps.back());
  }

  // Global node ids and their identification across glued faces.
  std::vector<int> offset(nc + 1, 0);
  for (int c = 0; c < nc; ++c) {
    const auto& n = domain.cuboids[c].nodes;
    offset[c + 1] = offset[c] + n[0] * n[1] * n[2];
  }
  const int total = offset[nc];
  std::vector<int> parent(total);
  std::iota(parent.begin(), parent.end(), 0);
  for (const polycube::GpcInterface& g : domain.interfaces) {
    const auto& na = domain.cuboids[g.cuboid[0]].nodes;
    const auto& nb = domain.cuboids[g.cuboid[1]].nodes;
    // The transition in grid-index units: exact integers.
    polycube::GpcTransition t;
    const std::array<double, 3> sa = {double(na[0] - 1), double(na[1] - 1), double(na[2] - 1)};
    const std::array<double, 3> sb = {double(nb[0] - 1), double(nb[1] - 1), double(nb[2] - 1)};
    std::array<int, 4> ca, cb;
    const auto fa = polycube::cube_face_corners(g.face[0]);
    for (int i = 0; i < 4; ++i) {
      ca[i] = fa[i];
      // Image of corner fa[i] under the unit transition: a corner of face[1].
      const Eigen::Vector3d unit((fa[i] & 1) * domain.cuboids[g.cuboid[0]].size[0],
                                 ((fa[i] >> 1) & 1) * domain.cuboids[g.cuboid[0]].size[1],
                                 ((fa[i] >> 2) & 1) * domain.cuboids[g.cuboid[0]].size[2]);
      const Eigen::Vector3d image = g.transition.apply(unit);
      int corner = 0;
      for (int a = 0; a < 3; ++a)
        if (image(a) > 0.5 * domain.cuboids[g.cuboid[1]].size[a]) corner |= 1 << a;
      cb[i] = corner;
    }
    if (!polycube::gpc_transition_from_corners(g.face[0], sa, ca, g.face[1], sb, cb, t))
      throw polycube::DecompositionError("volumetric map: interface of cut " + std::to_string(g.cut) +
                                         " has grids that do not match");
    const int axis = g.face[0] / 2;
    for (int k = 0; k < na[2]; ++k)
      for (int j = 0; j < na[1]; ++j)
        for (int i = 0; i < na[0]; ++i) {
          const std::array<int, 3> ijk = {i, j, k};
          if (ijk[axis] != (g.face[0] % 2 == 0 ? 0 : na[axis] - 1)) continue;
          const Eigen::Vector3d q = t.apply(Eigen::Vector3d(i, j, k));
          const int bi = static_cast<int>(std::lround(q(0))), bj = static_cast<int>(std::lround(q(1))),
                    bk = static_cast<int>(std::lround(q(2)));
          const int x = find(parent, offset[g.cuboid[0]] + grid_node_index(na, i, j, k));
          const int y = find(parent, offset[g.cuboid[1]] + grid_node_index(nb, bi, bj, bk));
          if (x != y) parent[std::max(x, y)] = std::min(x, y);
        }
  }

  // Positions: surface nodes by inverse lookup (from the first copy on an exposed face).
  std::vector<int> root(total);
  for (int id = 0; id < total; ++id) root[id] = find(parent, id);
  std::vector<char> on_surface(total, 0), on_boundary(total, 0);
  mesh::Positions xyz = mesh::Positions::Zero(total, 3);
  std::vector<char> placed(total, 0);
  std::vector<int> copies(total, 0);
  for (int id = 0; id < total; ++id) ++copies[root[id]];
  for (int c = 0; c < nc; ++c) {
    const auto& n = domain.cuboids[c].nodes;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          const int faces = node_faces(n, {i, j, k});
          if (faces == 0) continue;
          const int id = offset[c] + grid_node_index(n, i, j, k);
          const int r = root[id];
          on_boundary[r] = 1;
          bool exposed = false;
          for (int f = 0; f < 6; ++f)
            if ((faces >> f & 1) && domain.cuboids[c].face_interface[f] < 0) exposed = true;
          const Eigen::Vector3d uvw(double(i) / (n[0] - 1), double(j) / (n[1] - 1), double(k) / (n[2] - 1));
          if (exposed && !on_surface[r]) {
            on_surface[r] = 1;
            xyz.row(r) = locators[c].locate_uvw(uvw).transpose();
            placed[r] = 1;
          } else if (!placed[r]) {
            xyz.row(r) = locators[c].locate_uvw(uvw).transpose();  // on a disc: a start only
            placed[r] = 2;
          }
        }
  }
  // Warm start of interior nodes: transfinite interpolation in their cuboid.
  for (int c = 0; c < nc; ++c) {
    const auto& n = domain.cuboids[c].nodes;
    for (int k = 1; k + 1 < n[2]; ++k)
      for (int j = 1; j + 1 < n[1]; ++j)
        for (int i = 1; i + 1 < n[0]; ++i) {
          const std::array<int, 3> ijk = {i, j, k};
          Eigen::Vector3d guess = Eigen::Vector3d::Zero();
          for (int a = 0; a < 3; ++a) {
            std::array<int, 3> lo = ijk, hi = ijk;
            lo[a] = 0;
            hi[a] = n[a] - 1;
            const double t = double(ijk[a]) / (n[a] - 1);
            guess += (1.0 - t) * xyz.row(root[offset[c] + grid_node_index(n, lo[0], lo[1], lo[2])]).transpose() +
                     t * xyz.row(root[offset[c] + grid_node_index(n, hi[0], hi[1], hi[2])]).transpose();
          }
          xyz.row(root[offset[c] + grid_node_index(n, i, j, k)]) = guess.transpose() / 3.0;
        }
  }
  for (int r = 0; r < total; ++r)
    if (root[r] == r && copies[r] > 1) ++out.shared_nodes;

  // Eq. 3.1 over the union of the grids: unknowns are the roots not on the surface.
  progress.report("volumetric map", 0.35);
  std::vector<int> unknown(total, -1);
  int m = 0;
  for (int r = 0; r < total; ++r)
    if (root[r] == r && !on_surface[r]) unknown[r] = m++;
  std::vector<std::pair<int, int>> edges;
  for (int c = 0; c < nc; ++c) {
    const auto& n = domain.cuboids[c].nodes;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          const std::array<int, 3> ijk = {i, j, k};
          const int a_id = root[offset[c] + grid_node_index(n, i, j, k)];
          for (int a = 0; a < 3; ++a) {
            if (ijk[a] + 1 >= n[a]) continue;
            std::array<int, 3> nb = ijk;
            ++nb[a];
            const int b_id = root[offset[c] + grid_node_index(n, nb[0], nb[1], nb[2])];
            if (a_id != b_id) edges.push_back({std::min(a_id, b_id), std::max(a_id, b_id)});
          }
        }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  if (m > 0) {
    std::vector<linalg::Triplet> triplets;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 3), x0(m, 3);
    std::vector<double> degree(m, 0.0);
    for (const auto& [a, b] : edges) {
      for (const auto& [u, v] : {std::make_pair(a, b), std::make_pair(b, a)}) {
        if (unknown[u] < 0) continue;
        degree[unknown[u]] += 1.0;
        if (unknown[v] >= 0)
          triplets.push_back({unknown[u], unknown[v], -1.0});
        else
          rhs.row(unknown[u]) += xyz.row(v);
      }
    }
    for (int r = 0; r < total; ++r)
      if (unknown[r] >= 0) {
        triplets.push_back({unknown[r], unknown[r], degree[unknown[r]]});
        x0.row(unknown[r]) = xyz.row(r);
      }
    const linalg::CsrMatrix a = linalg::CsrMatrix::from_triplets(m, m, triplets);
    linalg::ConjugateGradient<linalg::IncompleteCholesky0> cg;
    cg.set_tolerance(options.tolerance);
    cg.compute(a);
    const Eigen::MatrixXd x = cg.solve(rhs, x0);
    out.cg_iterations = cg.iterations();
    for (int r = 0; r < total; ++r)
      if (unknown[r] >= 0) xyz.row(r) = x.row(unknown[r]);
  }

  // Per-cuboid grids, hex checks, untangling with every shared or surface node held.
  auto check = [&](GpcCuboidGrid& grid) {
    const mesh::HexGridQuality q = mesh::hex_grid_quality(grid.nodes, grid.xyz);
    grid.num_hexes = q.num_hexes;
    grid.num_inverted_hexes = q.num_inverted;
    grid.min_scaled_jacobian = q.min_scaled_jacobian;
  };
  out.grids.resize(nc);
  for (int c = 0; c < nc; ++c) {
    progress.report("grid untangling", 0.45 + 0.15 * c / nc);
    GpcCuboidGrid& grid = out.grids[c];
    grid.nodes = domain.cuboids[c].nodes;
    const int count = offset[c + 1] - offset[c];
    grid.xyz.resize(count, 3);
    for (int id = 0; id < count; ++id) grid.xyz.row(id) = xyz.row(root[offset[c] + id]);
    check(grid);
    out.harmonic_inverted_hexes += grid.num_inverted_hexes;
    if (options.untangle == GpcGridOptions::Untangle::On && grid.num_inverted_hexes > 0) {
      std::vector<char> fixed(count);
      for (int id = 0; id < count; ++id) {
        const int r = root[offset[c] + id];
        fixed[id] = on_surface[r] || copies[r] > 1;
      }
      out.untangled_nodes +=
          untangle_hex_grid(grid.nodes, fixed, grid.xyz, {}, share_of(progress, 0.45 + 0.15 * c / nc, 0.45 + 0.15 * (c + 1) / nc))
              .free_nodes;
      check(grid);
      for (int id = 0; id < count; ++id) xyz.row(root[offset[c] + id]) = grid.xyz.row(id);
    }
  }
  // All hexes over the shared nodes (root ids), with their faces on the surface.
  std::vector<std::array<int, 8>> hexes;
  std::vector<int> hex_cuboid;
  std::vector<std::uint8_t> surface_faces;
  for (int c = 0; c < nc; ++c) {
    const auto& n = domain.cuboids[c].nodes;
    for (int k = 0; k + 1 < n[2]; ++k)
      for (int j = 0; j + 1 < n[1]; ++j)
        for (int i = 0; i + 1 < n[0]; ++i) {
          std::array<int, 8> hex;
          for (int q = 0; q < 8; ++q)
            hex[q] = root[offset[c] + grid_node_index(n, i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1))];
          hexes.push_back(hex);
          hex_cuboid.push_back(c);
          const std::array<int, 3> ijk = {i, j, k};
          std::uint8_t mask = 0;
          for (int f = 0; f < 6; ++f) {
            const int a = f / 2;
            const bool at_end = f % 2 == 0 ? ijk[a] == 0 : ijk[a] == n[a] - 2;
            if (at_end && domain.cuboids[c].face_interface[f] < 0) mask |= std::uint8_t(1 << f);
          }
          surface_faces.push_back(mask);
        }
  }
  // Folds the held glued nodes kept: untangled again over all cuboids at once, the glued nodes
  // free and shared (one unknown per node), only the surface held.
  int folded = 0;
  for (const GpcCuboidGrid& grid : out.grids) folded += grid.num_inverted_hexes;
  if (options.untangle == GpcGridOptions::Untangle::On && folded > 0 && out.shared_nodes > 0) {
    progress.report("grid untangling", 0.6);
    std::vector<char> fixed(total);
    for (int r = 0; r < total; ++r) fixed[r] = root[r] != r || on_surface[r];
    // Only the folds near glued nodes: the others had every node they can move free before.
    std::vector<char> glued(total, 0);
    for (int r = 0; r < total; ++r) glued[r] = root[r] == r && copies[r] > 1 && !on_surface[r];
    HexGridUntangleOptions global;
    global.rounds = 1;
    out.untangled_nodes += untangle_hex_mesh(hexes, fixed, xyz, glued, global, nullptr, share_of(progress, 0.6, 0.7)).free_nodes;
    for (int c = 0; c < nc; ++c) {
      GpcCuboidGrid& grid = out.grids[c];
      for (int id = 0; id < offset[c + 1] - offset[c]; ++id) grid.xyz.row(id) = xyz.row(root[offset[c] + id]);
      check(grid);
    }
  }
  for (const GpcCuboidGrid& grid : out.grids) {
    out.cuboid_grid_inverted_hexes += grid.num_inverted_hexes;
    out.cuboid_grid_min_scaled_jacobian = std::min(out.cuboid_grid_min_scaled_jacobian, grid.min_scaled_jacobian);
  }
  // The output hex mesh: padded under the surface, then untangled with only the surface held.
  if (options.padding == GpcGridOptions::Padding::On) {
    progress.report("padding", 0.7);
    out.hex_mesh = pad_hex_mesh(xyz, hexes, hex_cuboid, surface_faces, options.padding_depth);
    if (options.untangle == GpcGridOptions::Untangle::On)
      out.untangled_nodes +=
          untangle_padded_mesh(construction, root, offset, total, options, out.hex_mesh, share_of(progress, 0.7, 0.95));
  } else {
    out.hex_mesh.xyz = xyz;
    out.hex_mesh.hexes = hexes;
    out.hex_mesh.hex_group = hex_cuboid;
    out.hex_mesh.padding.assign(hexes.size(), 0);
    out.hex_mesh.on_surface.assign(on_surface.begin(), on_surface.end());
  }
  const HexMeshQuality quality = hex_mesh_quality(out.hex_mesh);
  out.grid_inverted_hexes = quality.num_inverted;
  out.grid_min_scaled_jacobian = quality.min_scaled_jacobian;
  // Copies of one node in different grids (or twice in one) are compared as they are stored.
  std::vector<int> first(total, -1);
  double gap = 0.0;
  for (int c = 0; c < nc; ++c)
    for (int id = 0; id < offset[c + 1] - offset[c]; ++id) {
      const int r = root[offset[c] + id];
      if (first[r] < 0) {
        first[r] = offset[c] + id;
        continue;
      }
      int fc = 0;
      while (offset[fc + 1] <= first[r]) ++fc;
      gap = std::max(gap, (out.grids[c].xyz.row(id) - out.grids[fc].xyz.row(first[r] - offset[fc])).norm());
    }
  out.interface_gap_rel = bbox_diagonal > 0.0 ? gap / bbox_diagonal : 0.0;
  return out;
}

}  // namespace volspline::param
