// SPDX-License-Identifier: MIT
#include "core/pipeline/gpc_mesh2spline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <numeric>
#include <optional>

#include "core/common/error.h"
#include "core/linalg/parallel_for.h"
#include "core/mesh/hex_quality.h"
#include "core/param/cuboid_surface_map.h"
#include "core/pipeline/gpc_spline_measures.h"
#include "core/pipeline/stage_timer.h"
#include "core/spline/gpc_certificate_untangling.h"
#include "core/spline/gpc_jacobian_certificate.h"
#include "core/spline/gpc_spline_fitting.h"
#include "core/spline/spline_untangling.h"

namespace volspline::pipeline {

namespace {

// Share of the padded hex mesh's hexes folded (surface held) above which the GPC construction is
// retried with taller T-shape centres (GpcOptions::taller_centres_inverted_above). The shared
// solids' layouts fold at most 0.3 % of their hexes.
constexpr double kTallerCentresInvertedShare = 0.01;

void check_options(const GpcMesh2SplineOptions& o) {
  auto fail = [](const std::string& what) { throw Error("mesh2spline: " + what); };
  if (!(o.max_rms_rel > 0.0) || !std::isfinite(o.max_rms_rel)) fail("`max_rms_rel` must be a positive number");
  if (!(o.max_surface_error_rel >= 0.0) || !std::isfinite(o.max_surface_error_rel))
    fail("`max_surface_error_rel` must be a number ≥ 0");
  if (o.max_control_points < 64) fail("`max_control_points` must be ≥ 64");
  if (o.max_levels < 0 || o.max_levels > 30) fail("`max_levels` must be in [0, 30]");
  if (o.initial_cells < 1 || o.initial_cells > 64) fail("`initial_cells` must be in [1, 64]");
  if (!(o.refinement_ratio > 1.0 && o.refinement_ratio <= 4.0)) fail("`refinement_ratio` must be in (1, 4]");
  if (!(o.adaptive_growth > 1.0 && o.adaptive_growth <= 8.0)) fail("`adaptive_growth` must be in (1, 8]");
  if (o.measure_samples < 8 || o.measure_samples > 512) fail("`measure_samples` must be in [8, 512]");
  if (!(o.surface_weight > 0.0) || !std::isfinite(o.surface_weight)) fail("`surface_weight` must be a positive number");
  if (o.measure_lattice < 4 || o.measure_lattice > 256) fail("`measure_lattice` must be in [4, 256]");
  if (o.threads < 1) fail("`threads` must be ≥ 1");
  if (o.certificate_rounds < 0 || o.certificate_rounds > 64) fail("`certificate_rounds` must be in [0, 64]");
  if (!(o.hierarchical_from >= 1.0) || !std::isfinite(o.hierarchical_from)) fail("`hierarchical_from` must be ≥ 1");
  if (!(o.marking_fraction > 0.0 && o.marking_fraction <= 1.0)) fail("`marking_fraction` must be in (0, 1]");
  if (o.hierarchy_depth < 0 || o.hierarchy_depth > spline::GpcSpline::kMaxLevel)
    fail("`hierarchy_depth` must be 0 (automatic) or in [1, " + std::to_string(spline::GpcSpline::kMaxLevel) + "]");
  if (!(o.fit_damping >= 0.0 && o.fit_damping <= 1.0)) fail("`fit_damping` must be in [0, 1]");
  if (!(o.squeezed_below >= 0.0 && o.squeezed_below < 1.0)) fail("`squeezed_below` must be in [0, 1)");
}

// Fitting samples in the unit-box frame: every (cuboid, node) of the volumetric map's hex mesh
// at its grid parameter, and every surface vertex of every cuboid at its surface-map parameter.
struct FitData {
  spline::GpcSamples samples;
  std::vector<GpcSurfacePoint> surface;  // model units (for the measures)
  int dropped_nodes = 0;                 // grid nodes of inverted hexes left out (skip_folded)
};

// The padding layer (param::pad_hex_mesh) puts an inner copy of every surface node `depth` of the
// way to the mean centroid of its hexes, i.e. half a grid step inwards along each exposed face's
// normal in the cuboid's parameters; the copy's parameter moves by depth/2 of a step the same way.
// A shared node appears once per cuboid it belongs to, at the parameters of that cuboid (the
// transition maps them onto each other).
FitData fit_data(const GpcResult& gpc, double padding_depth, double surface_weight, bool centroids,
                 const Eigen::RowVector3d& centre, double diagonal, bool skip_folded) {
  const polycube::GpcDomain& domain = gpc.construction.domain;
  const param::HexMesh& hm = gpc.map.hex_mesh;
  FitData data;
  // skip_folded: the nodes of the hex mesh's inverted hexes (least corner scaled Jacobian ≤ 0)
  // that are not on the surface are a folded guess, not data.
  std::vector<char> folded(static_cast<std::size_t>(hm.xyz.rows()), 0);
  if (skip_folded)
    for (const std::array<int, 8>& hex : hm.hexes) {
      std::array<Eigen::Vector3d, 8> x;
      for (int q = 0; q < 8; ++q) x[q] = hm.xyz.row(hex[q]).transpose();
      if (mesh::hex_min_scaled_jacobian(x) > 0.0) continue;
      for (int q = 0; q < 8; ++q)
        if (hm.on_surface.empty() || !hm.on_surface[hex[q]]) folded[hex[q]] = 1;
    }
  std::vector<int> cuboid;
  std::vector<Eigen::Vector3d> uvw, xyz;
  auto add = [&](int c, const Eigen::Vector3d& p, const Eigen::RowVector3d& x) {
    cuboid.push_back(c);
    uvw.push_back(p);
    xyz.push_back(((x - centre) / diagonal).transpose());
  };
  const int rows = static_cast<int>(hm.xyz.rows());
  std::vector<int> seen(rows, -1);  // last cuboid that added the node
  std::size_t h = 0;
  for (int c = 0; c < static_cast<int>(domain.cuboids.size()); ++c) {
    const polycube::GpcCuboid& cu = domain.cuboids[c];
    const auto& n = cu.nodes;
    Eigen::Vector3d step;
    for (int a = 0; a < 3; ++a) step(a) = cu.size[a] / (n[a] - 1);
    for (int k = 0; k + 1 < n[2]; ++k)
      for (int j = 0; j + 1 < n[1]; ++j)
        for (int i = 0; i + 1 < n[0]; ++i, ++h) {
          for (int q = 0; q < 8; ++q) {
            const int id = hm.hexes[h][q];
            if (seen[id] == c) continue;
            seen[id] = c;
            const std::array<int, 3> g = {i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1)};
            Eigen::Vector3d p;
            for (int a = 0; a < 3; ++a) p(a) = step(a) * g[a];
            const int original = hm.copy_of.empty() ? -1 : hm.copy_of[id];
            if (folded[id]) {
              ++data.dropped_nodes;
              continue;
            }
            if (original < 0) {
              add(c, p, hm.xyz.row(id));
              continue;
            }
            Eigen::Vector3d inner = p;
            for (int a = 0; a < 3; ++a) {
              if (g[a] == 0 && cu.face_interface[2 * a] < 0) inner(a) += 0.5 * padding_depth * step(a);
              if (g[a] == n[a] - 1 && cu.face_interface[2 * a + 1] < 0) inner(a) -= 0.5 * padding_depth * step(a);
            }
            add(c, inner, hm.xyz.row(id));
            if (seen[original] != c) {
              seen[original] = c;
              add(c, p, hm.xyz.row(original));
            }
          }
        }
  }
  for (int c = 0; c < static_cast<int>(domain.cuboids.size()); ++c) {
    const polycube::CuboidSurface& surface = gpc.construction.surfaces[c];
    const mesh::Positions& map_uvw = gpc.map.surface_maps[c].uvw;
    const Eigen::Vector3d size(domain.cuboids[c].size[0], domain.cuboids[c].size[1], domain.cuboids[c].size[2]);
    for (int v = 0; v < surface.mesh.num_vertices(); ++v) {
      if (surface.surface_vertex[v] < 0) continue;
      const Eigen::Vector3d p = map_uvw.row(v).transpose().cwiseProduct(size);
      add(c, p, surface.mesh.positions.row(v));
      data.surface.push_back({c, p, surface.mesh.positions.row(v).transpose()});
    }
    if (!centroids) continue;
    for (int t = 0; t < surface.mesh.num_faces(); ++t) {
      if (surface.surface_face[t] < 0) continue;
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      Eigen::RowVector3d x = Eigen::RowVector3d::Zero();
      for (int k = 0; k < 3; ++k) {
        const int v = surface.mesh.triangles(t, k);
        p += map_uvw.row(v).transpose().cwiseProduct(size) / 3.0;
        x += surface.mesh.positions.row(v) / 3.0;
      }
      add(c, p, x);
      data.surface.push_back({c, p, x.transpose()});
    }
  }
  // The surface is data, the interior nodes a harmonic guess (Eq. 3.1): surface rows weigh more.
  data.samples.weight.assign(cuboid.size(), 1.0);
  for (std::size_t s = cuboid.size() - data.surface.size(); s < cuboid.size(); ++s) data.samples.weight[s] = surface_weight;
  data.samples.cuboid = std::move(cuboid);
  data.samples.uvw.resize(uvw.size(), 3);
  data.samples.values.resize(xyz.size(), 3);
  for (std::size_t s = 0; s < uvw.size(); ++s) {
    data.samples.uvw.row(s) = uvw[s].transpose();
    data.samples.values.row(s) = xyz[s].transpose();
  }
  return data;
}

// Control points before a fit (unit-box frame): the previous level's spline at each function's
// anchor, or at level 0 the trilinear blend of the anchor cuboid's corners. Functions the samples
// do not reach keep these.
Eigen::MatrixXd prior_points(const spline::GpcSpline& spline, const spline::GpcSpline* previous,
                             const Eigen::RowVector3d& centre, double diagonal) {
  Eigen::MatrixXd p(spline.num_functions(), 3);
  const polycube::GpcDomain& domain = spline.domain();
  for (int i = 0; i < spline.num_functions(); ++i) {
    const spline::GpcAnchor& anchor = spline.anchor(i);
    const polycube::GpcCuboid& c = domain.cuboids[anchor.cuboid];
    Eigen::Vector3d t;
    for (int a = 0; a < 3; ++a) t(a) = std::clamp(anchor.uvw(a) / c.size[a], 0.0, 1.0);
    if (previous) {
      Eigen::Vector3d uvw;
      for (int a = 0; a < 3; ++a) uvw(a) = t(a) * c.size[a];
      p.row(i) = previous->evaluate(anchor.cuboid, uvw).transpose();
      continue;
    }
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int corner = 0; corner < 8; ++corner) {
      double w = 1.0;
      for (int a = 0; a < 3; ++a) w *= (corner >> a & 1) ? t(a) : 1.0 - t(a);
      x += w * c.corner_xyz[corner];
    }
    p.row(i) = ((x.transpose() - centre) / diagonal);
  }
  return p;
}

// The fields fit_levels writes, back from a copy taken before it ran.
void restore_fit_stats(Mesh2SplineStats& stats, const Mesh2SplineStats& from) {
  stats.samples = from.samples;
  stats.level_history = from.level_history;
  stats.levels = from.levels;
  stats.rms_rel = from.rms_rel;
  stats.max_rel = from.max_rel;
  stats.control_points = from.control_points;
}

// Per cuboid axis, the mean length of the volumetric grid's lines along it in the unit-box
// frame: how long the solid is in that direction (the cuboid sizes follow the cut loops and poly-
// edges, which can be far thinner than the solid between them, e.g. kitten's tube).
std::vector<std::array<double, 3>> grid_line_lengths(const GpcResult& gpc, double diagonal) {
  std::vector<std::array<double, 3>> out;
  for (const param::GpcCuboidGrid& g : gpc.map.grids) {
    const auto& n = g.nodes;
    std::array<double, 3> mean{};
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3, e = (a + 2) % 3;
      double sum = 0.0;
      std::array<int, 3> idx{};
      for (idx[e] = 0; idx[e] < n[e]; ++idx[e])
        for (idx[b] = 0; idx[b] < n[b]; ++idx[b])
          for (idx[a] = 0; idx[a] + 1 < n[a]; ++idx[a]) {
            std::array<int, 3> next = idx;
            ++next[a];
            auto row = [&](const std::array<int, 3>& q) { return q[0] + n[0] * (q[1] + n[1] * q[2]); };
            sum += (g.xyz.row(row(next)) - g.xyz.row(row(idx))).norm();
          }
      mean[a] = sum / (static_cast<double>(n[b]) * n[e]) / diagonal;
    }
    out.push_back(mean);
  }
  return out;
}

// Distance of each of the last `count` samples (the surface vertices) to the spline's boundary
// near its parameter (gpc_surface_point_distance, the vertex side of hausdorff_rel), unit-box
// frame: a parameter that slid along the surface is no geometric error and is not refined for.
Eigen::VectorXd surface_misfit(const spline::GpcSpline& spline, const spline::GpcSamples& samples, std::size_t count) {
  const Eigen::Index m = samples.uvw.rows(), first = m - static_cast<Eigen::Index>(count);
  Eigen::VectorXd out(static_cast<Eigen::Index>(count));
  for (Eigen::Index s = first; s < m; ++s)
    out(s - first) = gpc_surface_point_distance(
        spline, {samples.cuboid[s], samples.uvw.row(s).transpose(), samples.values.row(s).transpose()});
  return out;
}

// F at the parameters of the last `count` samples (the surface vertices and centroids).
Eigen::MatrixX3d surface_values(const spline::GpcSpline& spline, const spline::GpcSamples& samples, std::size_t count) {
  const Eigen::Index m = samples.uvw.rows(), first = m - static_cast<Eigen::Index>(count);
  Eigen::MatrixX3d out(static_cast<Eigen::Index>(count), 3);
  for (Eigen::Index s = first; s < m; ++s)
    out.row(s - first) = spline.evaluate(samples.cuboid[s], samples.uvw.row(s).transpose()).transpose();
  return out;
}

// Sample ids of the surface vertices (misfit: surface_misfit) farther than `bound`, farthest first.
std::vector<int> surface_samples_beyond(const Eigen::VectorXd& misfit, const spline::GpcSamples& samples,
                                        double bound) {
  const int first = static_cast<int>(samples.uvw.rows() - misfit.size());
  std::vector<int> out;
  for (Eigen::Index k = 0; k < misfit.size(); ++k)
    if (misfit(k) > bound) out.push_back(first + static_cast<int>(k));
  std::stable_sort(out.begin(), out.end(), [&](int a, int b) { return misfit(a - first) > misfit(b - first); });
  return out;
}

// The fewest functions of a uniform spline over the same GPC (the knot count rule of the levels,
// `cells` intervals along the longest grid line length) whose plain least-squares fit reaches the
// result's rms_rel: doubling `cells` from initial_cells, then bisection (stats
// uniform_control_points, uniform_rms_rel; left at -1 if the samples run out first).
void compare_uniform(const polycube::GpcDomain& domain, const spline::GpcSamples& samples,
                     const std::vector<std::array<double, 3>>& lengths, double longest, int initial_cells,
                     const Eigen::RowVector3d& centre, double diagonal, Mesh2SplineStats& stats) {
  const int count = static_cast<int>(samples.uvw.rows());
  auto uniform = [&](int cells, int* functions) {
    spline::GpcSplineOptions so;
    so.intervals = spline::gpc_uniform_intervals(domain, longest / cells, &lengths);
    spline::GpcSpline u(domain, so);
    *functions = u.num_functions();
    if (4 * u.num_functions() > count) return -1.0;
    u.set_points(prior_points(u, nullptr, centre, diagonal));
    return spline::fit_gpc_spline(u, samples).rms_error;
  };
  int lo = initial_cells, hi = -1, functions = 0, hi_functions = 0;
  double hi_rms = 0.0;
  for (int cells = initial_cells; cells <= 4096; cells *= 2) {
    const double r = uniform(cells, &functions);
    if (r < 0.0) return;
    if (r <= stats.rms_rel) {
      hi = cells, hi_rms = r, hi_functions = functions;
      break;
    }
    lo = cells;
  }
  if (hi < 0) return;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    const double r = uniform(mid, &functions);
    if (r >= 0.0 && r <= stats.rms_rel)
      hi = mid, hi_rms = r, hi_functions = functions;
    else
      lo = mid;
  }
  stats.uniform_control_points = hi_functions;
  stats.uniform_rms_rel = hi_rms;
}

// Splits start from a level with at least two knot intervals along every cuboid axis: a tube
// one cell across (a torus's first level) folds along its four long edges, which local splits
// do not reach, where the next uniform level has room.
bool two_intervals_per_axis(const spline::GpcSpline& spline) {
  for (int c = 0; c < spline.num_cuboids(); ++c)
    for (int a = 0; a < 3; ++a)
      if (spline.intervals(c)[a] < 2) return false;
  return true;
}

double longest_size(const polycube::GpcDomain& domain) {
  double longest = 0.0;
  for (const polycube::GpcCuboid& c : domain.cuboids)
    for (double s : c.size) longest = std::max(longest, s);
  return longest;
}

// spline::untangle_spline on every cuboid's patch restricted to its box: only the functions whose
// support lies inside the box and vanishes on its faces move (each belongs to this cuboid alone),
// so the surface fit and both sides of every glued face stay as they are; then the certificate
// rounds over all cuboids at once (spline::untangle_gpc_certificate), which move global
// functions, shared ones as one control point. RoundsFirst: the rounds' first attempt alone
// before all that, which ends the untangling where it certifies every cell (see
// GpcMesh2SplineOptions::untangle_start). Returns the functions that were free to move, the path
// taken and the certificate passes run (Mesh2SplineStats::untangle_path, certificate_passes).
// progress: "<stage>: certificate round K" (RoundsFirst), "<stage>: cuboids" (the share of
// cuboids done) at every pass of a cuboid, then "<stage>: certificate round K", over [from, to]
// in that order; each is where a cancel request stops the job.
struct Untangled {
  int free_functions = 0;
  bool rounds_alone = false;  // the rounds' first attempt alone certified every cell
  int certificate_passes = 0, local_passes = 0;  // over all attempts, the rounds-first one included
};

Untangled untangle_cuboids(spline::GpcSpline& spline, const spline::GpcSamples& samples, int threads,
                           int certificate_rounds, GpcMesh2SplineOptions::UntangleStart start,
                           spline::JacobianCertificateCache& certificates, const Progress& progress,
                           const std::string& stage, double from, double to) {
  // The rounds' own label is "untangle certificate K: N cells uncertified", K counting from 1 in
  // every attempt (untangle_gpc_certificate): shown as the stage's certificate round, over [lo, hi].
  const auto round_progress = [&](double lo, double hi) {
    return Progress([&progress, &stage, lo, hi](const std::string& label, double fraction) {
      const std::string own = "untangle certificate ";
      const std::string round = label.compare(0, own.size(), own) == 0 ? label.substr(own.size()) : label;
      progress.report(stage + ": certificate round " + round, lo + (hi - lo) * fraction);
      return true;
    });
  };
  spline::SplineUntangleOptions rounds;
  rounds.certificate_rounds = certificate_rounds;
  const bool rounds_first = start == GpcMesh2SplineOptions::UntangleStart::RoundsFirst;
  const double passes_from = rounds_first ? from + (to - from) / 3.0 : from;
  Untangled out;
  if (rounds_first) {
    // Not in the thesis: most fits fold in a few hundred cells that the rounds alone certify,
    // where the per-cuboid passes, which scan and polish every cuboid's lattice, cost as much as
    // the rounds (README, mesh2spline step 4). The fit is kept as a copy, not as its points: the
    // cell polynomials follow moved points by adding their change, so points set back would round
    // differently from the fit.
    const spline::GpcSpline fit = spline;
    spline::SplineUntangleOptions first = rounds;
    first.certificate_attempts = 1;
    const spline::SplineUntangleResult r =
        spline::untangle_gpc_certificate(spline, samples, first, round_progress(from, passes_from), &certificates);
    out.certificate_passes = r.certificate_passes;
    out.local_passes = r.local_passes;
    if (r.final_uncertified == 0) {
      out.free_functions = r.free_functions;
      out.rounds_alone = true;
      return out;
    }
    spline = fit;
  }
  const double longest_side = longest_size(spline.domain());
  const int nc = spline.num_cuboids();
  // The cuboids' passes report from their threads: one report at a time, the count of cuboids
  // done as the fraction (the first half of [passes_from, to]; the certificate rounds take the rest).
  std::mutex report_mutex;
  int cuboids_done = 0;
  const double middle = 0.5 * (passes_from + to);
  const auto report_cuboids = [&](bool finished) {
    std::lock_guard<std::mutex> lock(report_mutex);
    if (finished) ++cuboids_done;
    progress.report(stage + ": cuboids", passes_from + (middle - passes_from) * cuboids_done / nc);
  };
  // Every cuboid starts from the fitted points and its moves are written back in cuboid order, so
  // the cuboids are independent jobs: the same result on any number of threads.
  std::vector<Eigen::MatrixXd> moved(static_cast<std::size_t>(nc));
  std::vector<int> free(static_cast<std::size_t>(nc), 0);
  linalg::parallel_for(threads, nc, [&](int c) {
    std::vector<Eigen::Index> rows;
    for (std::size_t s = 0; s < samples.cuboid.size(); ++s)
      if (samples.cuboid[s] == c) rows.push_back(static_cast<Eigen::Index>(s));
    Eigen::MatrixX3d uvw(rows.size(), 3), xyz(rows.size(), 3);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      uvw.row(r) = samples.uvw.row(rows[r]);
      xyz.row(r) = samples.values.row(rows[r]);
    }
    // The same node density in every cuboid: the default lattice over the longest cuboid side.
    spline::SplineUntangleOptions uo;
    // A polish pass that unfolds under half its folded lattice points is undone and its folds
    // left to the certificate rounds below, which move boundary functions too (kitten: a pass
    // over 200,000 lattice points unfolds 42 → 35 there).
    uo.polish_min_unfolded = 0.5;
    // The polish lattice no finer than the measured one (measure_lattice's 64³ cell centres per
    // cuboid): on a finer one a pass's few coarse free functions span hundreds of thousands of
    // nodes, and the certificate rounds below hold the folds between its points anyway.
    uo.polish_max_per_axis = 64;
    const auto& size = spline.domain().cuboids[c].size;
    const double longest = *std::max_element(size.begin(), size.end());
    uo.lattice = std::clamp(static_cast<int>(std::lround(uo.lattice * longest / longest_side)), 8, uo.lattice);
    spline::TSpline patch = spline.patch(c);
    // Where a face is continued the patch reaches past the box: only the box is this cuboid's
    // (clamped to the patch's domain: its end knots are the box's up to rounding). The
    // certificate rounds run over all cuboids at once below (their functions cross the faces).
    uo.certificate_rounds = 0;
    for (Eigen::Index r = 0; r < uvw.rows(); ++r)
      uvw.row(r) = uvw.row(r).cwiseMax(patch.domain_min().transpose()).cwiseMin(patch.domain_max().transpose());
    bool continued = false;
    for (int f = 0; f < 6; ++f) continued = continued || spline.face_join(c, f) == spline::GpcFaceJoin::Continued;
    if (continued)
      uo.region = {{Eigen::Vector3d::Zero().cwiseMax(patch.domain_min()),
                    Eigen::Vector3d(size[0], size[1], size[2]).cwiseMin(patch.domain_max())}};
    const Progress cuboid_progress([&](const std::string&, double) {
      report_cuboids(false);
      return true;
    });
    free[c] = spline::untangle_spline(patch, uvw, xyz, uo, cuboid_progress).free_functions;
    moved[c] = patch.points();
    report_cuboids(true);
  });
  Eigen::MatrixXd points = spline.points();
  for (int c = 0; c < nc; ++c) {
    const std::vector<int>& ids = spline.patch_function_ids(c);
    for (std::size_t j = 0; j < ids.size(); ++j) points.row(ids[j]) = moved[c].row(static_cast<Eigen::Index>(j));
  }
  spline.set_points(std::move(points));
  // GpcMesh2SplineOptions::certificate_rounds (16 by default): the rounds stop once every cell is
  // certified or the count stalls for 3 rounds, so only a spline whose count still falls runs past 8.
  const spline::SplineUntangleResult certified =
      spline::untangle_gpc_certificate(spline, samples, rounds, round_progress(middle, to), &certificates);
  out.free_functions = std::accumulate(free.begin(), free.end(), 0) + certified.free_functions;
  out.certificate_passes += certified.certificate_passes;
  out.local_passes += certified.local_passes;
  return out;
}


}  // namespace

const char* refinement_name(GpcMesh2SplineOptions::Refinement refinement) {
  switch (refinement) {
    case GpcMesh2SplineOptions::Refinement::Adaptive: return "adaptive";
    case GpcMesh2SplineOptions::Refinement::Hierarchical: return "hierarchical";
    default: return "uniform";
  }
}

GpcMesh2SplineResult run_gpc_mesh2spline(const mesh::TriangleMesh& mesh, const std::string& name,
                                         const GpcMesh2SplineOptions& options, const Progress& progress) {
  check_options(options);
  Mesh2SplineStats stats;
  StageTimer timer(stats.times_s);
  // The GPC construction is the first 60 % of the job.
  const Progress gpc_progress([&](const std::string& stage, double fraction) {
    progress.report(stage == "done" ? "domain built" : stage, 0.6 * fraction);
    return true;
  });
  // The fit samples every hex-mesh node at its grid parameter, so the surface nodes must stay
  // where the surface maps put them: the last quality stage of the hex mesh, which slides them
  // over the whole surface, is left out here. The padded mesh's untanglers keep the mean
  // reference cell, and the construction is not rebuilt with taller T-shape centres: choosing
  // either by the padded mesh's own quality does not predict what the spline's fit and
  // untangling need (README, "Any genus"), and without the quality stage most meshes would pay
  // for the second construction.
  // For the same reason the padded mesh's second untangling, which slides face nodes to open the
  // folds that the first one leaves with the surface held, is left out: those folds are the
  // spline untangling's to open.
  GpcOptions gpc_options = options.gpc;
  gpc_options.grid.min_quality_sweeps = 0;
  gpc_options.grid.padded_reference = param::GpcGridOptions::PaddedReference::MeanCell;
  gpc_options.grid.face_sliding = param::GpcGridOptions::FaceSliding::Off;
  gpc_options.taller_centres_below = -1.0;
  // A few folds of the padded mesh are the spline untangling's to open; a percent of its hexes
  // folded is a T-shape centre whose layout folds the volume around the junction (held-out
  // twocup: 2.5 %, a cup's handles), which the spline untangling opens only by moving the
  // surface. That construction is retried with taller centres (§3.3.2's T-to-cube layout).
  gpc_options.taller_centres_inverted_above = kTallerCentresInvertedShare;
  // A tip crowded into a spot of its cuboid face needs cells finer than the hierarchy reaches.
  gpc_options.grid.squeezed_below = options.squeezed_below;
  // A genus-0 solid comes here only when its one-cuboid map is squeezed (thin limbs crowded
  // into spots of a cube face): fewer folds of that one cuboid's padded mesh do not make it the
  // better domain for the spline (a chair's legs fitted through one cuboid miss the surface).
  gpc_options.one_cuboid_fallback = GpcOptions::OneCuboidFallback::OnlyIfUnbuilt;
  const GpcResult gpc = run_gpc(mesh, name, gpc_options, gpc_progress);
  timer.end_stage("gpc");
  const polycube::GpcDomain& domain = gpc.construction.domain;
  stats.genus = gpc.stats.genus;
  stats.t_shapes = gpc.stats.t_shapes;
  stats.cuboids = gpc.stats.cuboids;
  stats.ill_points = gpc.stats.ill_points;
  stats.interfaces = gpc.stats.interfaces;
  stats.flipped_triangles = gpc.stats.flipped_triangles;
  stats.surface_least_density = std::numeric_limits<double>::infinity();
  for (const param::CuboidSurfaceMap& map : gpc.map.surface_maps) {
    stats.squeeze_rounds = std::max(stats.squeeze_rounds, map.squeeze_rounds);
    stats.surface_least_density = std::min(stats.surface_least_density, map.least_density);
  }
  stats.grid_inverted_hexes = gpc.stats.grid_inverted_hexes;
  stats.grid_min_scaled_jacobian = gpc.stats.grid_min_scaled_jacobian;
  for (const auto& [name, text] : gpc.stats.retries()) stats.domain_retries[name] = text;
  // A squeezed surface map (the rescue ran, or a spot stays below squeezed_below) crowds a tip
  // into a spot of its face: deeper splits resolve it, and the triangles' centroids give those
  // splits samples between the vertices (a level holds at most a quarter of the samples'
  // functions, and the spline is held between the vertices, where the Hausdorff distance is).
  const bool squeezed = param::squeezed_map(stats.squeeze_rounds, stats.surface_least_density, options.squeezed_below);
  const int hierarchy_depth =
      options.hierarchy_depth > 0 ? options.hierarchy_depth : squeezed ? kSqueezedHierarchyDepth : kHierarchyDepth;
  const bool centroids =
      options.surface_samples == GpcMesh2SplineOptions::SurfaceSamples::VerticesAndCentroids ||
      (options.surface_samples == GpcMesh2SplineOptions::SurfaceSamples::Auto && squeezed);
  stats.hierarchy_depth = hierarchy_depth;
  stats.centroid_samples = centroids;

  // Unit-box frame of the input (results do not depend on where the model sits or its units).
  const Eigen::RowVector3d lo = mesh.positions.colwise().minCoeff(), hi = mesh.positions.colwise().maxCoeff();
  const Eigen::RowVector3d centre = 0.5 * (lo + hi);
  const double diagonal = (hi - lo).norm();
  const double padding_depth =
      options.gpc.grid.padding == param::GpcGridOptions::Padding::On ? options.gpc.grid.padding_depth : 0.0;
  const FitData data = fit_data(gpc, padding_depth, options.surface_weight, centroids, centre, diagonal, false);

  const std::vector<std::array<double, 3>> lengths = grid_line_lengths(gpc, diagonal);
  double longest = 0.0;
  for (const auto& l : lengths) longest = std::max({longest, l[0], l[1], l[2]});
  const bool adaptive = options.refinement == GpcMesh2SplineOptions::Refinement::Adaptive;
  // No knot interval below the volumetric grid's step: every function keeps grid nodes.
  std::vector<std::array<double, 3>> grid_step;
  for (std::size_t c = 0; c < gpc.map.grids.size(); ++c) {
    std::array<double, 3> step{};
    for (int a = 0; a < 3; ++a) step[a] = domain.cuboids[c].size[a] / std::max(1, gpc.map.grids[c].nodes[a] - 1);
    grid_step.push_back(step);
  }
  const bool hierarchical = options.refinement == GpcMesh2SplineOptions::Refinement::Hierarchical;
  // Knot refinement (§4.3, Algorithm 4) until rms_rel ≤ max_rms_rel, the levels or the budget run
  // out: level 0 uniform, then per level either the misfit's marking on knot intervals or the
  // uniform spacing shrunk by refinement_ratio. Writes the fields of stats that restore_fit_stats
  // puts back; stage: the prefix of the levels' stage names (and of their progress labels);
  // progress runs from `from` over `width`.
  auto fit_levels = [&](const FitData& fit, const std::string& stage, double from, double width) {
    stats.samples = static_cast<int>(fit.samples.cuboid.size());
    stats.level_history.clear();
    std::optional<spline::GpcSpline> best;
    std::vector<int> beyond;  // surface samples of the last level beyond max_surface_error_rel
    double spacing = longest / options.initial_cells;
    bool splitting = false;  // Hierarchical: past the uniform levels
    bool rebase = false;     // Hierarchical: the splits stalled, the next level is the next uniform one
    // level counts the uniform levels (max_levels), step every fit (stage names, level_history).
    for (int level = 0, step = 0; level <= options.max_levels && step <= options.max_levels + 40; ++step) {
      std::string label = stage;
      std::replace(label.begin(), label.end(), '_', ' ');
      progress.report(label + std::to_string(step), from + width * level / (options.max_levels + 1));
      splitting = !rebase && (splitting || (hierarchical && best && stats.rms_rel <= options.hierarchical_from * options.max_rms_rel &&
                                            two_intervals_per_axis(*best)));
      rebase = false;
      std::optional<spline::GpcSpline> next;
      std::vector<int> marked;
      if (splitting) {
        // About 16 new functions per split (children shared between neighbours).
        const int n = best->num_functions();
        const int room = static_cast<int>(std::min<double>((options.adaptive_growth - 1.0) * n / 16.0,
                                                           (options.max_control_points - n) / 16.0));
        if (room >= 1)
          marked = spline::gpc_marked_functions(*best, fit.samples, options.marking_fraction, room,
                                                hierarchy_depth, beyond);
        // Every function with misfit at hierarchy_depth: the next uniform level instead.
        splitting = !marked.empty();
      }
      if (splitting) {
        next = best->refined(marked);  // F carried over exactly: the fit starts from the last level
      } else {
        spline::GpcSplineOptions so;
        if (adaptive && best)
          so.knot_lines = spline::gpc_refined_knot_lines(*best, fit.samples, options.adaptive_growth, grid_step, beyond);
        else
          so.intervals = spline::gpc_uniform_intervals(domain, spacing, &lengths);
        spacing /= options.refinement_ratio;
        next.emplace(domain, so);
        ++level;
        // After stalled splits, the first uniform level with more functions than the splits reached.
        while (hierarchical && best && next->num_functions() <= best->num_functions() &&
               next->num_functions() <= options.max_control_points) {
          so.intervals = spline::gpc_uniform_intervals(domain, spacing, &lengths);
          spacing /= options.refinement_ratio;
          next.emplace(domain, so);
        }
      }
      spline::GpcSpline& candidate = *next;
      // More functions than a quarter of the samples: the least squares would be fixed mostly by the
      // regularization, not by data (and CG slows down by orders of magnitude).
      if (best && (candidate.num_functions() > options.max_control_points ||
                   4 * candidate.num_functions() > stats.samples))
        break;
      if (!splitting) candidate.set_points(prior_points(candidate, best ? &*best : nullptr, centre, diagonal));
      const double last_rms = stats.rms_rel;
      spline::GpcSplineFitOptions fit_options;
      fit_options.regularization = options.fit_damping;
      const spline::GpcSplineFitReport report = spline::fit_gpc_spline(candidate, fit.samples, fit_options);
      timer.end_stage(stage + std::to_string(step));
      stats.levels = step;
      stats.rms_rel = report.rms_error;  // unit diagonal: already relative
      stats.max_rel = report.max_error;
      stats.control_points = candidate.num_functions();
      const Eigen::VectorXd misfit = surface_misfit(candidate, fit.samples, fit.surface.size());
      if (options.max_surface_error_rel > 0.0)
        beyond = surface_samples_beyond(misfit, fit.samples, options.max_surface_error_rel);
      stats.level_history.push_back({candidate.num_functions(), report.rms_error, misfit.size() ? misfit.maxCoeff() : 0.0});
      best = std::move(candidate);
      if (stats.rms_rel <= options.max_rms_rel && beyond.empty()) break;
      // A split step that gains under 2 % of the rms has met functions at hierarchy_depth only: the
      // next level is the next uniform one, and splitting goes on from there.
      if (splitting && stats.rms_rel > 0.98 * last_rms) rebase = true;
    }
    return std::move(*best);
  };
  spline::GpcSpline fitted = fit_levels(data, "fit_level_", 0.6, 0.3);
  stats.continued_interfaces = fitted.num_continued_interfaces();
  if (options.compare_uniform == GpcMesh2SplineOptions::CompareUniform::On) {
    progress.report("uniform comparison", 0.88);
    compare_uniform(domain, data.samples, lengths, longest, options.initial_cells, centre, diagonal, stats);
    timer.end_stage("compare_uniform");
  }
  stats.negative_jacobian_fraction_fit = -1.0;
  // The untangler's last certificates: the final one below recomputes only the cells moved since.
  spline::JacobianCertificateCache certificates;
  if (options.untangle == GpcMesh2SplineOptions::Untangle::On) {
    progress.report("untangle", 0.9);
    // The unit-box frame: distances are already relative to the diagonal.
    const Eigen::MatrixX3d fitted_surface = surface_values(fitted, data.samples, data.surface.size());
    const auto set_untangled = [&stats](const Untangled& u) {
      stats.untangled_control_points = u.free_functions;
      stats.untangle_path = u.rounds_alone ? "rounds" : "passes";
      stats.certificate_passes = u.certificate_passes;
      stats.local_certificate_passes = u.local_passes;
    };
    set_untangled(untangle_cuboids(fitted, data.samples, options.threads, options.certificate_rounds,
                                   options.untangle_start, certificates, progress, "untangle", 0.9, 0.91));
    const auto surface_shift = [](const Eigen::MatrixX3d& before, const Eigen::MatrixX3d& after) {
      return before.rows() ? (after - before).rowwise().norm().maxCoeff() : 0.0;
    };
    stats.untangle_surface_shift_rel =
        surface_shift(fitted_surface, surface_values(fitted, data.samples, data.surface.size()));
    timer.end_stage("untangle");
    // Cells left uncertified: a second fit without the grid nodes of the hex mesh's inverted
    // hexes, untangled the same way; the spline with fewer uncertified cells, then the higher
    // det_j_lower_bound_rel, is kept. Not in the thesis: the interior nodes are a harmonic guess
    // (Eq. 3.1), and where the padded mesh stays inverted the least squares copy its fold into
    // the spline, where the untangler's sample term then holds it; the spline's smoothness fills
    // the gap instead. Only a second attempt: on most solids the folded nodes' neighbours keep
    // the fit closer to the mesh, and their fit certifies.
    const spline::JacobianCertificate first =
        spline::certify_gpc_jacobian(fitted, spline::gpc_certificate_options(), &certificates);
    const FitData unfolded = options.refit_folded_nodes && !first.uncertified.empty()
                                 ? fit_data(gpc, padding_depth, options.surface_weight, centroids, centre, diagonal, true)
                                 : FitData();
    if (unfolded.dropped_nodes > 0) {
      progress.report("refit without folded grid nodes", 0.91);  // the first untangling's end, so no step back
      const Mesh2SplineStats kept = stats;
      // The first spline's certificates are dropped, not kept beside the second's: the final
      // certificate recomputes them if the first is kept (armadillo: 350 MB for 232,591 cells).
      certificates = spline::JacobianCertificateCache();
      spline::GpcSpline second = fit_levels(unfolded, "refit_level_", 0.91, 0.005);
      progress.report("refit: untangle", 0.915);
      spline::JacobianCertificateCache second_certificates;
      const Eigen::MatrixX3d second_surface = surface_values(second, unfolded.samples, unfolded.surface.size());
      // The first untangling showed that the rounds alone leave cells uncertified on this solid:
      // the second one starts with the passes (on large solids, armadillo's 230,000 cells, the
      // rounds alone would cost as much as the whole untangling again).
      const Untangled second_untangled =
          untangle_cuboids(second, unfolded.samples, options.threads, options.certificate_rounds,
                           GpcMesh2SplineOptions::UntangleStart::PassesFirst, second_certificates, progress,
                           "refit: untangle", 0.915, 0.92);
      timer.end_stage("refit_untangle");
      const spline::JacobianCertificate c =
          spline::certify_gpc_jacobian(second, spline::gpc_certificate_options(), &second_certificates);
      if (c.uncertified.size() < first.uncertified.size() ||
          (c.uncertified.size() == first.uncertified.size() && c.det_j_lower_bound_rel > first.det_j_lower_bound_rel)) {
        fitted = std::move(second);
        certificates = std::move(second_certificates);
        set_untangled(second_untangled);
        stats.untangle_surface_shift_rel =
            surface_shift(second_surface, surface_values(fitted, unfolded.samples, unfolded.surface.size()));
        stats.refit_dropped_nodes = unfolded.dropped_nodes;
      } else {
        restore_fit_stats(stats, kept);
      }
    }
  }

  // Measures in the unit-box frame, against the normalized input surface.
  progress.report("measure", 0.92);
  mesh::TriangleMesh unit_surface = gpc.surface;
  unit_surface.positions = (unit_surface.positions.rowwise() - centre) / diagonal;
  std::vector<GpcSurfacePoint> surface = data.surface;
  for (GpcSurfacePoint& p : surface) p.xyz = ((p.xyz.transpose() - centre) / diagonal).transpose();
  GpcSplineMeasureOptions mo;
  mo.surface_samples = options.measure_samples;
  mo.lattice = options.measure_lattice;
  mo.seed = options.seed;
  const GpcSplineMeasures m = measure_gpc_spline(fitted, unit_surface, surface, 1.0, mo);
  stats.hausdorff_rel = m.hausdorff_rel;
  stats.rms_geo_rel = m.rms_geo_rel;
  stats.min_scaled_jacobian = m.min_scaled_jacobian;
  stats.negative_jacobian_fraction = m.negative_jacobian_fraction;
  stats.jacobian_samples = m.jacobian_samples;
  stats.lattice_negative_fraction = m.lattice_negative_fraction;
  stats.lattice_samples = m.lattice_samples;
  stats.semi_standard_max_error = m.semi_standard_max_error;
  stats.interface_gap_rel = m.interface_gap_rel;
  stats.interface_normal_jump_deg = m.interface_normal_jump_deg;
  timer.end_stage("measure");

  // DESIGN §6: the Bernstein certificate of det J on every cell of every cuboid.
  progress.report("certificate", 0.97);
  record_certificate(stats, spline::certify_gpc_jacobian(fitted, spline::gpc_certificate_options(), &certificates));
  timer.end_stage("certificate");

  // Back to model units: Σ B_i ≡ 1, so mapping the control points maps F.
  Eigen::MatrixXd points = fitted.points();
  points = (points * diagonal).rowwise() + centre;
  fitted.set_points(std::move(points));
  progress.report("done", 1.0);
  return {std::move(fitted), std::move(stats)};
}

}  // namespace volspline::pipeline
