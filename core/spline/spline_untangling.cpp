// SPDX-License-Identifier: MIT
#include "core/spline/spline_untangling.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/mesh/hex_quality.h"
#include "core/spline/bezier_extraction.h"
#include "core/spline/edge_crease.h"
#include "core/spline/jacobian_certificate.h"
#include "core/spline/tspline_fitting.h"
#include "core/spline/untangle_pass.h"

namespace volspline::spline {

namespace {

using detail::AxisNodes;
using detail::lexicographic_less;
using detail::merge_points;
using detail::uncertified_points;


// The dense check between passes: per axis, check_per_interval centres of equal parts of every
// knot interval plus the boundary layers (as make_pass_nodes); its points with scaled Jacobian below
// min_scaled_jacobian that the interior functions can move, in lexicographic order.
std::vector<Eigen::Vector3d> folded_points(const TSpline& spline, const SplineUntangleOptions& options) {
  const Eigen::Vector3d lo = detail::region_min(spline, options), hi = detail::region_max(spline, options);
  std::array<std::vector<double>, 3> coords;
  for (int a = 0; a < 3; ++a) {
    std::vector<double>& t = coords[a];
    const std::vector<double> lines = detail::region_knot_lines(spline, options, a);
    const int per = options.check_per_interval;
    for (std::size_t i = 0; i + 1 < lines.size(); ++i)
      for (int q = 0; q < per; ++q) t.push_back(lines[i] + (lines[i + 1] - lines[i]) * (q + 0.5) / per);
    const double first = t.front() - lo(a), last = hi(a) - t.back();
    for (double d : options.boundary_layers)
      if (d > 0.0) {
        t.push_back(lo(a) + d * first);
        t.push_back(hi(a) - d * last);
      }
    std::sort(t.begin(), t.end());
  }
  std::vector<Eigen::Vector3d> folded;
  spline.evaluate_lattice_with_jacobian(coords, [&](int i, int j, int k, const double*, const double* jacobian) {
    if (mesh::scaled_jacobian(Eigen::Map<const Eigen::Matrix3d>(jacobian)) < options.min_scaled_jacobian)
      folded.emplace_back(coords[0][i], coords[1][j], coords[2][k]);
  });
  // Points where the interior functions carry under kMinMovableShare of |w∇B| (next to the
  // cuboid's edges, or the fitted surface itself flipped) are beyond their reach: left out.
  detail::PointGradients gradients;
  auto interior = [&](int f) { return !detail::held_function(spline.knots()[f], lo, hi, options); };
  auto out_of_reach = [&](const Eigen::Vector3d& p) {
    gradients.at(spline, p);
    double total = 0.0;
    return gradients.movable_share(spline, interior, &total) < detail::kMinMovableShare * total;
  };
  folded.erase(std::remove_if(folded.begin(), folded.end(), out_of_reach), folded.end());
  return folded;  // lattice order is lexicographic in (w, v, u); sorted by the caller's merge
}

// The polish lattice: per axis the centres of equal parts of the domain as wide as the finest
// knot interval of any axis (bunny: 1/64, the 64³ cell centres), at least min_per_axis and at
// most max_per_axis of them, all scanned. No boundary layers: 1/512 from the faces det J is at
// its most fragile, and holding them cost bunny 12 s for 175 such points.
std::array<AxisNodes, 3> finest_nodes(const TSpline& spline, const SplineUntangleOptions& options, int min_per_axis,
                                     int max_per_axis) {
  const Eigen::Vector3d lo = detail::region_min(spline, options), hi = detail::region_max(spline, options);
  double finest = 1.0;  // a fraction of the region's extent
  for (int a = 0; a < 3; ++a) {
    const std::vector<double> lines = detail::region_knot_lines(spline, options, a);
    for (std::size_t i = 0; i + 1 < lines.size(); ++i)
      finest = std::min(finest, (lines[i + 1] - lines[i]) / (hi(a) - lo(a)));
  }
  const int per_axis =
      std::min(max_per_axis, std::max(min_per_axis, static_cast<int>(std::ceil(1.0 / finest - 1e-9))));
  std::array<AxisNodes, 3> nodes;
  for (int a = 0; a < 3; ++a) {
    for (int q = 0; q < per_axis; ++q) nodes[a].t.push_back(lo(a) + (hi(a) - lo(a)) * (q + 0.5) / per_axis);
    nodes[a].scanned.assign(per_axis, 1);
  }
  return nodes;
}

// The lattice points with scaled Jacobian ≤ threshold, in lattice order.
std::vector<Eigen::Vector3d> bad_lattice_points(const TSpline& spline, const std::array<AxisNodes, 3>& nodes,
                                                double threshold) {
  std::vector<Eigen::Vector3d> bad;
  spline.evaluate_lattice_with_jacobian({nodes[0].t, nodes[1].t, nodes[2].t},
                                        [&](int i, int j, int k, const double*, const double* jacobian) {
                                          if (mesh::scaled_jacobian(Eigen::Map<const Eigen::Matrix3d>(jacobian)) <= threshold)
                                            bad.emplace_back(nodes[0].t[i], nodes[1].t[j], nodes[2].t[k]);
                                        });
  std::sort(bad.begin(), bad.end(), lexicographic_less);
  return bad;
}

// The cells of the spline's knot-line grid where one of the functions is non-zero, increasing.
std::vector<int> cells_of_functions(const TSpline& spline, const std::vector<int>& functions) {
  std::vector<char> hit(spline.num_cells(), 0);
  std::array<int, 3> n;
  for (int a = 0; a < 3; ++a) n[a] = static_cast<int>(spline.knot_lines(a).size()) - 1;
  for (int f : functions) {
    std::array<int, 3> first, last;
    for (int a = 0; a < 3; ++a) {
      const std::vector<double>& lines = spline.knot_lines(a);
      const LocalKnots& r = spline.knots()[f][a];
      first[a] = static_cast<int>(std::lower_bound(lines.begin(), lines.end(), r[0]) - lines.begin());
      last[a] = static_cast<int>(std::lower_bound(lines.begin(), lines.end(), r[4]) - lines.begin());
    }
    for (int k = first[2]; k < last[2]; ++k)
      for (int j = first[1]; j < last[1]; ++j)
        for (int i = first[0]; i < last[0]; ++i) hit[i + n[0] * (j + n[1] * k)] = 1;
  }
  std::vector<int> out;
  for (int c = 0; c < spline.num_cells(); ++c)
    if (hit[c]) out.push_back(c);
  return out;
}

// After the rounds: the cells still uncertified whose det J is negative on or next to a cuboid
// edge where the surface is near-flat get that crease tilted convex (convex_edge_creases). det J on a cuboid edge is set by the
// bd-control-points next to it alone (§4.3.1); a near-flat crease fitted a hair past flat leaves
// it slightly negative there, which the passes' barrier, holding points on the edge where det J
// cannot rise above 0 for a flat crease, does not lift. The step runs last so that the rounds
// first remove the real folds (with the data term) and the tilt only settles what is left; the
// cells in the moved functions' supports are certified again, and the tilt is undone unless it
// leaves fewer uncertified cells.
void tilt_creases(TSpline& spline, const std::vector<UncertifiedCell>& uncertified, const SplineUntangleOptions& options,
                  SplineUntangleResult& total) {
  const Eigen::MatrixXd before = spline.points();
  EdgeCreaseOptions crease_options;
  crease_options.exposed_faces = options.exposed_faces;
  const EdgeCreaseResult creases = convex_edge_creases(spline, uncertified, crease_options);
  if (creases.moved.empty()) return;
  const std::vector<int> touched = cells_of_functions(spline, creases.moved);
  int count = 0;
  for (const UncertifiedCell& u : uncertified) count += !std::binary_search(touched.begin(), touched.end(), u.cell);
  for (int cell : touched)
    count += certify_bezier_cell(extract_bezier_cell(spline, cell), {}).status != JacobianCellStatus::Certified;
  if (count >= static_cast<int>(uncertified.size())) {
    spline.set_points(before);
    return;
  }
  total.crease_edges = creases.edges;
  total.crease_functions = static_cast<int>(creases.moved.size());
  total.final_uncertified = count;
}

// DESIGN §6: the untangler works toward the certificate. Each round certifies every cell and
// holds the folded points of the uncertified ones (those of earlier rounds too) in passes on the
// polish lattice: an exact, small active set where the lattices above see only their own
// points. Interior functions first, as everywhere in the untangler; the boundary functions near
// a point move too (kept on the surface by the data term) where the interior ones carry under
// kMinMovableShare of |w∇B| (det J on a cuboid edge depends on the boundary control points
// alone) or where its cell stayed uncertified from the round before (a face whose own
// parameterization folds). A round may unfold some cells and fold others between the lattice
// points; the rounds keep the spline of the round with the fewest uncertified cells. After a
// round without progress, surface samples may slide along the surface (boundary_tangent_weight):
// a folded face parameterization cannot unfold while every sample pins its own parameter.
void certificate_rounds(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                        const SplineUntangleOptions& options, const Progress& progress, double steps,
                        detail::NodeCache& cache, SplineUntangleResult& total) {
  const std::array<AxisNodes, 3> fine = finest_nodes(spline, options, options.lattice, options.polish_max_per_axis);
  SplineUntangleOptions inner_options = options;
  inner_options.rings = 0;
  SplineUntangleOptions boundary_options = inner_options;
  boundary_options.exposed_faces = polycube::CubeFaceSet();
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  auto interior = [&](int f) { return !touches_exposed_face(spline.knots()[f], lo, hi, options.exposed_faces); };
  detail::PointGradients gradients;
  auto needs_boundary = [&](const Eigen::Vector3d& p) {
    gradients.at(spline, p);
    double all = 0.0;
    return gradients.movable_share(spline, interior, &all) < detail::kMinMovableShare * all;
  };
  std::vector<Eigen::Vector3d> held_inner, held_boundary;
  std::vector<int> previous_cells;  // uncertified in the round before, increasing
  detail::CertificateRounds rounds;
  std::vector<UncertifiedCell> best;  // the uncertified cells of the round with the fewest
  JacobianCertificateCache certificates;  // cells a round's passes did not move keep their result
  for (int round = 0;; ++round) {
    JacobianCertificate certificate =
        certify_jacobian_in_box(spline, spline.domain_min(), spline.domain_max(), {}, 0, &certificates);
    const int uncertified = static_cast<int>(certificate.uncertified.size());
    if (round == 0) total.initial_uncertified = uncertified;
    if (uncertified < rounds.final_uncertified()) best = certificate.uncertified;
    if (rounds.stop(round, uncertified, spline.points(), options.certificate_rounds)) {
      if (uncertified > rounds.final_uncertified()) spline.set_points(rounds.take_best_points());
      else best = std::move(certificate.uncertified);
      total.final_uncertified = rounds.final_uncertified();
      if (!best.empty()) tilt_creases(spline, best, options, total);
      return;
    }
    progress.report("untangle certificate " + std::to_string(round + 1) + ": " + std::to_string(uncertified) +
                        " cells uncertified",
                    (options.passes + options.polish_rounds + round) / steps);
    std::vector<Eigen::Vector3d> inner, boundary;
    std::vector<int> cells;
    for (const UncertifiedCell& u : certificate.uncertified) {
      cells.push_back(u.cell);
      const bool again = std::binary_search(previous_cells.begin(), previous_cells.end(), u.cell);
      for (const Eigen::Vector3d& p : uncertified_points(spline, u))
        (again || needs_boundary(p) ? boundary : inner).push_back(p);
    }
    previous_cells = std::move(cells);
    merge_points(held_inner, std::move(inner));
    merge_points(held_boundary, std::move(boundary));
    for (int side = 0; side < 2; ++side) {
      const std::vector<Eigen::Vector3d>& seeds = side == 0 ? held_inner : held_boundary;
      if (seeds.empty()) continue;
      const SplineUntangleResult r =
          detail::untangle_pass(spline, fine, uvw, xyz, seeds, side == 0 ? inner_options : boundary_options,
                                detail::PassSeeds::PointsOnly, cache, side == 0 ? held_boundary : held_inner,
                                side == 0 || rounds.stalled() == 0 ? 1.0 : options.boundary_tangent_weight);
      ++total.certificate_passes;
      total.free_functions += r.free_functions;
      total.iterations += r.iterations;
    }
  }
}

}  // namespace

SplineUntangleResult untangle_spline(TSpline& spline, const Eigen::MatrixX3d& uvw, const Eigen::MatrixX3d& xyz,
                                     const SplineUntangleOptions& options, const Progress& progress) {
  assert(spline.dimension() == 3 && uvw.rows() == xyz.rows());
  assert(options.lattice >= 4 && options.seed_stride >= 1 && options.rings >= 0 && options.max_support_steps >= 4);
  assert(options.passes >= 1);
  assert(options.energy_stride >= 1 && options.seed_stride % options.energy_stride == 0);
  assert(options.nodes_per_knot_interval >= 0 && options.stop_margin >= 0.0 && options.stop_margin < 1.0);
  assert(options.check_per_interval >= 0);
  assert(options.polish_rounds >= 0 && options.polish_max_per_axis >= 2);
  assert(options.polish_min_unfolded >= 0.0 && options.polish_min_unfolded < 1.0);
  assert(options.certificate_rounds >= 0);
  assert(!options.region || (((*options.region)[0].array() < (*options.region)[1].array()).all() &&
                             ((*options.region)[0].array() >= spline.domain_min().array()).all() &&
                             ((*options.region)[1].array() <= spline.domain_max().array()).all()));
  assert(options.boundary_tangent_weight >= 0.0 && options.boundary_tangent_weight <= 1.0);
  assert(std::all_of(options.boundary_layers.begin(), options.boundary_layers.end(),
                     [](double d) { return d >= 0.0 && d < 1.0; }));
  SplineUntangleResult total;
  detail::NodeCache cache;  // node Jacobians from one pass to the next
  SplineUntangleOptions pass_options = options;
  std::vector<Eigen::Vector3d> extra;
  const double steps = options.passes + options.polish_rounds + (options.region ? 0 : options.certificate_rounds);
  for (int pass = 0; pass < options.passes; ++pass) {
    progress.report("untangle pass " + std::to_string(pass + 1), pass / steps);
    const SplineUntangleResult r =
        detail::untangle_pass(spline, detail::make_pass_nodes(spline, pass_options), uvw, xyz, extra, pass_options,
                              detail::PassSeeds::ScanAndPoints, cache);
    if (pass == 0) {
      total.seeds = r.seeds;
      total.initial_negative = r.initial_negative;
    }
    total.scanned = r.scanned;
    total.final_negative = r.final_negative;
    total.final_min_scaled = r.final_min_scaled;
    total.free_functions += r.free_functions;
    total.points += r.points;
    total.samples += r.samples;
    total.iterations += r.iterations;
    if (options.check_per_interval == 0) {
      if (r.seeds == 0 || r.final_negative == 0) break;
      // Each pass lets coarser functions move: the few seeds the fine ones could not fix.
      pass_options.max_support_steps *= 2;
      continue;
    }
    if (pass + 1 == options.passes) break;  // no pass left to use a check
    // Bad points between the nodes join every later pass as scattered nodes.
    std::vector<Eigen::Vector3d> bad = folded_points(spline, options);
    if (bad.empty() && r.final_negative == 0) break;
    std::sort(bad.begin(), bad.end(), lexicographic_less);
    const std::size_t before = extra.size();
    extra.insert(extra.end(), bad.begin(), bad.end());
    std::inplace_merge(extra.begin(), extra.begin() + before, extra.end(), lexicographic_less);
    // The later passes are seeded by held points: no rings around the seeds and no coarser
    // functions (both leave fewer folded points and cost less).
    pass_options.rings = 0;
    extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
    total.check_points = static_cast<int>(extra.size());
  }
  // Polish (not in the thesis): the points of the finest lattice still folded seed local passes
  // whose nodes are that lattice, so the barrier holds every lattice point the free functions
  // touch; the passes above hold their nodes only, and folds between them remain (bunny: 8 of
  // the 64³ cell centres after 3 passes with dense checks). A pass that unfolds under
  // polish_min_unfolded of its seeds is undone: its folds need functions it may not move.
  if (options.polish_rounds > 0) {
    const std::array<AxisNodes, 3> fine = finest_nodes(spline, options, options.lattice, options.polish_max_per_axis);
    SplineUntangleOptions polish_options = options;
    polish_options.rings = 0;
    std::size_t previous = std::numeric_limits<std::size_t>::max();
    std::vector<Eigen::Vector3d> bad = bad_lattice_points(spline, fine, 0.0);
    for (int round = 0; round < options.polish_rounds; ++round) {
      progress.report("untangle polish " + std::to_string(round + 1), (options.passes + round) / steps);
      total.polish_folded = static_cast<int>(bad.size());
      if (bad.empty() || bad.size() >= previous) break;  // done, or no progress
      previous = bad.size();
      const Eigen::MatrixXd before = options.polish_min_unfolded > 0.0 ? spline.points() : Eigen::MatrixXd();
      const SplineUntangleResult r =
          detail::untangle_pass(spline, fine, uvw, xyz, bad, polish_options, detail::PassSeeds::PointsOnly, cache);
      ++total.polish_passes;
      total.free_functions += r.free_functions;
      total.iterations += r.iterations;
      if (r.free_functions == 0) break;
      std::vector<Eigen::Vector3d> after = bad_lattice_points(spline, fine, 0.0);
      if (static_cast<double>(bad.size() - std::min(after.size(), bad.size())) <
          options.polish_min_unfolded * static_cast<double>(bad.size())) {
        spline.set_points(before);
        cache.current = false;
        break;
      }
      bad = std::move(after);
      total.polish_folded = static_cast<int>(bad.size());
    }
  }
  if (options.certificate_rounds > 0 && !options.region) certificate_rounds(spline, uvw, xyz, options, progress, steps, cache, total);
  return total;
}

}  // namespace volspline::spline
