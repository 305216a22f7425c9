// SPDX-License-Identifier: MIT
#include "core/pipeline/mesh2spline_job.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <unordered_set>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "core/common/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/hex_quality.h"
#include "core/mesh/mesh_report.h"
#include "core/mesh/unit_box.h"
#include "core/param/cuboid_surface_locator.h"
#include "core/param/volumetric_grid_map.h"
#include "core/pipeline/mesh2spline_measures.h"
#include "core/pipeline/solid_mesh.h"
#include "core/pipeline/stage_timer.h"
#include "core/polycube/cube_faces.h"
#include "core/polycube/cuboid_layout.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/hierarchical_fitting.h"
#include "core/spline/hierarchical_refinement.h"
#include "core/spline/jacobian_repair.h"
#include "core/spline/spline_untangling.h"
#include "core/spline/tspline_fitting.h"

namespace volspline::pipeline {

namespace {

// Meshes with at least this many vertices are fitted at their vertices only (no face centroids).
constexpr int kDenseMeshVertices = 8000;
// Automatic cuboid layouts whose surface maps choose_layout compares, and how much less
// anisotropic (root mean square of log(σ_max / σ_min)) another's map must be to replace the
// first (farthest-apart corners): a layout that squeezes a limb stands out by far more than
// this, while near ties among good layouts do not predict the fit.
constexpr int kLayoutCandidates = 6;
constexpr double kLayoutAnisotropyMargin = 0.1;

void check_options(const Mesh2SplineOptions& o) {
  auto fail = [](const std::string& what) { throw Error("mesh2spline: " + what); };
  if (!(o.max_rms_rel > 0.0) || !std::isfinite(o.max_rms_rel))
    fail("`max_rms_rel` must be a positive number, got " + std::to_string(o.max_rms_rel));
  if (o.max_control_points < 64) fail("`max_control_points` must be ≥ 64");
  if (o.max_levels < 0 || o.max_levels > 10) fail("`max_levels` must be in [0, 10]");
  if (o.area_balance_iterations < 0 || o.area_balance_iterations > 20)
    fail("`area_balance_iterations` must be in [0, 20]");
  if (!(o.squeezed_below >= 0.0 && o.squeezed_below < 1.0)) fail("`squeezed_below` must be in [0, 1)");
  if (o.initial_cells < 1 || o.initial_cells > 64) fail("`initial_cells` must be in [1, 64]");
  if (o.grid_nodes != 0 && (o.grid_nodes < 5 || o.grid_nodes > 256))
    fail("`grid_nodes` must be 0 (auto) or in [5, 256]");
  if (!(o.smoothing >= 0.0) || !std::isfinite(o.smoothing)) fail("`smoothing` must be ≥ 0");
  if (!(o.min_scaled_jacobian >= 0.0 && o.min_scaled_jacobian <= 0.5))
    fail("`min_scaled_jacobian` (the Jacobian repair target) must be in [0, 0.5]");
  if (!(o.max_surface_error_rel > 0.0) || !std::isfinite(o.max_surface_error_rel))
    fail("`max_surface_error_rel` must be a positive number");
  if (o.measure_samples < 8 || o.measure_samples > 512) fail("`measure_samples` must be in [8, 512]");
}

// A stage's own fractions reported as [lo, hi] of the job's; cancellation passes through.
Progress job_share(const Progress& progress, double lo, double hi) {
  return Progress([&progress, lo, hi](const std::string& stage, double fraction) {
    progress.report(stage, lo + (hi - lo) * fraction);
    return true;
  });
}

// The validated, outward-oriented half-edge mesh; throws on anything mesh2spline refuses.
mesh::HalfedgeMesh validated_mesh(const mesh::TriangleMesh& input, const std::string& name, const Progress& progress) {
  SolidMesh solid = validate_solid_mesh(input, name, "mesh2spline", progress);
  if (solid.report.genus != 0)
    throw Error("mesh '" + name + "': genus " + std::to_string(solid.report.genus) +
                "; mesh2spline maps the solid to one cuboid and needs genus 0 (volspline gpc builds the "
                "multi-cuboid domain of any genus)");
  return std::move(solid.mesh);
}

// Transfinite guess: mean of the three linear interpolations between opposite cube faces.
Eigen::Vector3d transfinite_point(const param::CuboidSurfaceLocator& locator, const Eigen::Vector3d& uvw) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d lo = uvw, hi = uvw;
    lo(a) = 0.0;
    hi(a) = 1.0;
    sum += (1.0 - uvw(a)) * locator.locate_uvw(lo) + uvw(a) * locator.locate_uvw(hi);
  }
  return sum / 3.0;
}

Eigen::MatrixX3d greville_prior(const spline::TSpline& spline, const param::CuboidSurfaceLocator& locator) {
  Eigen::MatrixX3d prior(spline.num_functions(), 3);
  for (int i = 0; i < spline.num_functions(); ++i) {
    Eigen::Vector3d g;
    for (int a = 0; a < 3; ++a) {
      const auto& r = spline.knots()[i][a];
      g(a) = (r[1] + r[2] + r[3]) / 3.0;
    }
    prior.row(i) = transfinite_point(locator, g).transpose();
  }
  return prior;
}

spline::TSpline uniform_tspline(const std::array<int, 3>& cells) {
  std::array<std::vector<double>, 3> knots;
  int count = 1;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> grid(cells[a] + 1);
    for (int i = 0; i <= cells[a]; ++i) grid[i] = static_cast<double>(i) / cells[a];
    knots[a] = spline::boundary_restricted_knots(grid);
    count *= cells[a] + 3;
  }
  // Function lists: the job changes the control points after every fit and evaluates a few
  // 10⁵ points, so per-cell polynomials would be rebuilt more often than they pay off.
  return spline::from_bspline_volume(spline::BsplineVolume(knots, Eigen::MatrixXd::Zero(count, 3)),
                                     spline::TSplineAcceleration::FunctionLists);
}

std::array<int, 3> cells_for(const Eigen::Vector3d& dims, int longest_cells) {
  std::array<int, 3> cells;
  for (int a = 0; a < 3; ++a)
    cells[a] = std::max(1, static_cast<int>(std::lround(longest_cells * dims(a) / dims.maxCoeff())));
  return cells;
}

struct Samples {
  Eigen::MatrixX3d uvw, xyz;
  std::vector<char> on_boundary;  // uvw on the boundary of [0,1]³ (a surface sample, Eq. 4.4)
};

Samples to_samples(const std::vector<Eigen::Vector3d>& uvw, const std::vector<Eigen::Vector3d>& xyz) {
  Samples s;
  s.uvw.resize(uvw.size(), 3);
  s.xyz.resize(xyz.size(), 3);
  s.on_boundary.resize(uvw.size());
  for (std::size_t i = 0; i < uvw.size(); ++i) {
    s.uvw.row(i) = uvw[i].transpose();
    s.xyz.row(i) = xyz[i].transpose();
    s.on_boundary[i] = (uvw[i].array() <= 0.0).any() || (uvw[i].array() >= 1.0).any();
  }
  return s;
}

// Surface samples of the exact surface map on the boundary faces of a refinement cell: k×k
// points per boundary face of the cell, so every boundary leaf holds surface samples however
// fine it is (the mesh vertices leave stretched parts of the map unsampled).
void add_cell_surface_samples(const param::CuboidSurfaceLocator& locator, const Eigen::Vector3d& lo,
                              const Eigen::Vector3d& hi, int k, std::vector<Eigen::Vector3d>& uvw,
                              std::vector<Eigen::Vector3d>& xyz) {
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      if (side == 0 ? lo(a) > 0.0 : hi(a) < 1.0) continue;
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
          Eigen::Vector3d p;
          p(a) = side;
          p(b) = lo(b) + (hi(b) - lo(b)) * (i + 0.5) / k;
          p(c) = lo(c) + (hi(c) - lo(c)) * (j + 0.5) / k;
          uvw.push_back(p);
          xyz.push_back(locator.locate_uvw(p));
        }
    }
}

// free_functions: empty = all control points.
spline::TSplineFitResult fit(spline::TSpline& ts, const Samples& samples, const Eigen::MatrixX3d& prior,
                             const Mesh2SplineOptions& options, int laplacian_nodes,
                             const std::vector<int>& free_functions = {}) {
  spline::TSplineFitOptions fit_options;
  fit_options.smoothing = options.smoothing;
  fit_options.laplacian_nodes = laplacian_nodes;
  // Relative CG residual: 1e-5 instead of 1e-6 halves the iterations again (bunny_closed
  // levels 2–3: 27 + 38 → 13 + 20 iterations); the fitted rms_rel moves by under 1e-5 of the
  // diagonal on bunny, bimba and sphere (bunny: 59 more control points, 5,335).
  fit_options.tolerance = 1e-5;
  if (options.fit == Mesh2SplineFit::Grid && !free_functions.empty())
    return spline::fit_tspline_local(ts, samples.uvw, samples.xyz, prior, free_functions, fit_options);
  if (options.fit == Mesh2SplineFit::Grid)
    return spline::fit_tspline(ts, samples.uvw, samples.xyz, prior, fit_options);
  return spline::fit_tspline_meshless(ts, samples.uvw, samples.xyz, prior, fit_options);
}

Eigen::VectorXd sample_errors(const spline::TSpline& ts, const Samples& samples) {
  const Eigen::MatrixXd f = ts.evaluate_batch(samples.uvw);
  return (f - samples.xyz).rowwise().norm();
}

// Blending functions of `refined` that are new or whose support overlaps a split cell: the
// only ones whose least-squares optimum moves much after a local refinement (the refined
// spline reproduces the previous fit, which was optimal elsewhere). Increasing ids.
std::vector<int> functions_to_refit(const spline::TSpline& refined, const spline::TSpline& previous,
                                    const spline::RefinementGrid& grid, const std::vector<int>& split_cells) {
  constexpr int kBuckets = 16;
  std::vector<std::vector<int>> buckets(kBuckets * kBuckets * kBuckets);
  auto bucket_range = [](double lo, double hi, int& first, int& last) {
    first = std::clamp(static_cast<int>(lo * kBuckets), 0, kBuckets - 1);
    last = std::clamp(static_cast<int>(hi * kBuckets), 0, kBuckets - 1);
  };
  for (std::size_t c = 0; c < split_cells.size(); ++c) {
    std::array<int, 3> first, last;
    for (int a = 0; a < 3; ++a)
      bucket_range(grid.cell_min(split_cells[c])(a), grid.cell_max(split_cells[c])(a), first[a], last[a]);
    for (int k = first[2]; k <= last[2]; ++k)
      for (int j = first[1]; j <= last[1]; ++j)
        for (int i = first[0]; i <= last[0]; ++i) buckets[i + kBuckets * (j + kBuckets * k)].push_back(static_cast<int>(c));
  }
  const std::unordered_set<spline::BlendingKnots, spline::KnotsHash> old_knots(previous.knots().begin(),
                                                                             previous.knots().end());
  std::vector<int> ids;
  for (int f = 0; f < refined.num_functions(); ++f) {
    const spline::BlendingKnots& r = refined.knots()[f];
    bool free = old_knots.count(r) == 0;
    std::array<int, 3> first, last;
    for (int a = 0; a < 3; ++a) bucket_range(r[a][0], r[a][4], first[a], last[a]);
    for (int k = first[2]; k <= last[2] && !free; ++k)
      for (int j = first[1]; j <= last[1] && !free; ++j)
        for (int i = first[0]; i <= last[0] && !free; ++i)
          for (int c : buckets[i + kBuckets * (j + kBuckets * k)]) {
            const Eigen::Vector3d& lo = grid.cell_min(split_cells[c]);
            const Eigen::Vector3d& hi = grid.cell_max(split_cells[c]);
            bool overlap = true;
            for (int a = 0; a < 3 && overlap; ++a) overlap = r[a][0] < hi(a) && lo(a) < r[a][4];
            if (overlap) {
              free = true;
              break;
            }
          }
    if (free) ids.push_back(f);
  }
  return ids;
}

double rms(const Eigen::VectorXd& e) { return e.size() ? std::sqrt(e.squaredNorm() / e.size()) : 0.0; }

// run_hierarchical_fitting on the solid's samples (§4.3.1 boundary restricted control grid): the grid or
// meshless fit of the geometry, marking by the rms and surface targets, a refinement over the
// control point budget ends the fit.
class SolidFit final : public spline::HierarchicalFit, public spline::MarkingRule {
 public:
  SolidFit(spline::TSpline spline, spline::RefinementGrid grid, const param::CuboidSurfaceLocator& locator,
           const Mesh2SplineOptions& options, int laplacian_nodes, double diagonal,
           std::vector<Eigen::Vector3d> sample_uvw, std::vector<Eigen::Vector3d> sample_xyz, Mesh2SplineStats& stats,
           StageTimer& timer, const Progress& progress)
      : ts(std::move(spline)), refinement(std::move(grid)), samples(to_samples(sample_uvw, sample_xyz)),
        locator_(locator), options_(options), laplacian_nodes_(laplacian_nodes),
        target_(options.max_rms_rel * diagonal), surface_target_(options.max_surface_error_rel * diagonal),
        sample_uvw_(std::move(sample_uvw)), sample_xyz_(std::move(sample_xyz)), stats_(stats), timer_(timer),
        progress_(progress) {
    prior_ = greville_prior(ts, locator_);
    ts.set_points(prior_);
  }

  void fit(int level) override {
    progress_.report("fit level " + std::to_string(level), 0.3 + 0.4 * level / (options_.max_levels + 1));
    pipeline::fit(ts, samples, prior_, options_, laplacian_nodes_, refit_);
    errors = sample_errors(ts, samples);
    timer_.end_stage("fit_level_" + std::to_string(level));
    stats_.levels = level;
    // FittingError(g): the worst sample error inside each leaf cell, the worst
    // surface sample error, and the cell's share of the squared error.
    const std::vector<int> leaves = refinement.leaves();
    cell_error_.assign(leaves.empty() ? 0 : leaves.back() + 1, 0.0);
    cell_surface_error_.assign(cell_error_.size(), 0.0);
    cell_sse_.assign(cell_error_.size(), 0.0);
    surface_max_ = 0.0;
    for (Eigen::Index s = 0; s < samples.uvw.rows(); ++s) {
      const int leaf = refinement.leaf_of(samples.uvw.row(s).transpose());
      cell_error_[leaf] = std::max(cell_error_[leaf], errors(s));
      cell_sse_[leaf] += errors(s) * errors(s);
      if (samples.on_boundary[s]) {
        cell_surface_error_[leaf] = std::max(cell_surface_error_[leaf], errors(s));
        surface_max_ = std::max(surface_max_, errors(s));
      }
    }
  }

  int num_control_points() const override { return ts.num_functions(); }

  std::optional<spline::FitStopReason> stop(int level) override {
    if (rms(errors) <= target_ && surface_max_ <= surface_target_) return spline::FitStopReason::Target;
    if (level >= options_.max_levels) return spline::FitStopReason::MaxLevels;
    return std::nullopt;
  }

  spline::Marking mark(int) override {
    // Candidates for the rms: cells whose worst sample exceeds twice the rms target. Of these,
    // the fewest (largest squared error first, ties by id) that hold twice the squared error
    // the rms target asks to remove (bulk marking), and at most 25% of the cells per level, so
    // refinement stays where the error is and stops widening once the target is near.
    const std::vector<int> leaves = refinement.leaves();
    std::vector<int> marked;
    if (rms(errors) > target_) {
      for (int leaf : leaves)
        if (cell_error_[leaf] > 2.0 * target_) marked.push_back(leaf);
      std::stable_sort(marked.begin(), marked.end(), [&](int a, int b) { return cell_sse_[a] > cell_sse_[b]; });
      const double total_sse = errors.squaredNorm();
      const double excess = total_sse - target_ * target_ * static_cast<double>(errors.size());
      std::size_t count = 0;
      for (double held = 0.0; count < marked.size() && held < 2.0 * excess; ++count) held += cell_sse_[marked[count]];
      const std::size_t quota = std::max<std::size_t>(1, leaves.size() / 4);
      marked.resize(std::min({std::max<std::size_t>(count, 1), quota, marked.size()}));
    }
    // The rms alone leaves small badly fitted surface parts (ears, tips) that dominate the
    // Hausdorff distance: every cell whose worst surface sample misses the surface target is
    // refined too (a 2D set of cells, so it does not blow up the control points).
    for (int leaf : leaves)
      if (cell_surface_error_[leaf] > surface_target_) marked.push_back(leaf);
    std::sort(marked.begin(), marked.end());
    marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
    return {std::move(marked), spline::FitStopReason::NoCells};
  }

  bool refine(const std::vector<int>& cells, int level) override {
    spline::RefinementGrid next_grid = refinement;
    spline::TSpline refined = next_grid.split(ts, cells, spline::TSplineAcceleration::FunctionLists);
    timer_.end_stage("refine_level_" + std::to_string(level));
    if (refined.num_functions() > options_.max_control_points) return false;
    refit_ = functions_to_refit(refined, ts, next_grid, cells);
    ts = std::move(refined);
    refinement = std::move(next_grid);
    for (int leaf : refinement.leaves())
      if (refinement.cell_level(leaf) == level + 1)
        add_cell_surface_samples(locator_, refinement.cell_min(leaf), refinement.cell_max(leaf), 2, sample_uvw_,
                                 sample_xyz_);
    samples = to_samples(sample_uvw_, sample_xyz_);
    // The refined spline equals the previous fit: it is the prior of the next level.
    prior_ = ts.points();
    return true;
  }

  spline::OverBudget over_budget() const override { return spline::OverBudget::Stop; }

  spline::TSpline ts;
  spline::RefinementGrid refinement;
  Samples samples;
  Eigen::VectorXd errors;  // per sample, model units, of the last fit

 private:
  const param::CuboidSurfaceLocator& locator_;
  const Mesh2SplineOptions& options_;
  const int laplacian_nodes_;
  const double target_, surface_target_;
  std::vector<Eigen::Vector3d> sample_uvw_, sample_xyz_;
  Mesh2SplineStats& stats_;
  StageTimer& timer_;
  const Progress& progress_;
  Eigen::MatrixX3d prior_;
  std::vector<int> refit_;  // control points to re-fit after a refinement (empty: all)
  std::vector<double> cell_error_, cell_surface_error_, cell_sse_;
  double surface_max_ = 0.0;
};

// Bounding-box diagonal of the referenced vertices; throws on a zero-size box.
double bbox_diagonal(const mesh::HalfedgeMesh& hm, const std::string& name) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (int v = 0; v < hm.num_vertices(); ++v)
    if (hm.vertex_halfedge(v) != mesh::no_id) {
      lo = lo.cwiseMin(hm.vertex_position(v));
      hi = hi.cwiseMax(hm.vertex_position(v));
    }
  const double diagonal = (hi - lo).norm();
  if (!(diagonal > 0.0)) throw Error("mesh '" + name + "': zero-size bounding box");
  return diagonal;
}

// Mean poly-edge length per cuboid axis (at least 1e-3 of the longest).
Eigen::Vector3d cuboid_dims(const mesh::HalfedgeMesh& hm, const polycube::CuboidLayout& layout) {
  Eigen::Vector3d dims = Eigen::Vector3d::Zero();
  for (int e = 0; e < polycube::num_cube_edges; ++e) {
    const auto& path = layout.poly_edges[e];
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
      dims(e / 4) += 0.25 * (hm.vertex_position(path[i + 1]) - hm.vertex_position(path[i])).norm();
  }
  return dims.cwiseMax(1e-3 * dims.maxCoeff());
}

// Area-weighted root mean square over the triangles of log(σ_max / σ_min), the anisotropy of the
// surface map (§3.4.1) onto the cuboid's faces scaled to `dims`: 0 for a conformal map.
double surface_map_anisotropy(const mesh::HalfedgeMesh& hm, const param::CuboidSurfaceMap& map,
                              const Eigen::Vector3d& dims) {
  double total = 0.0, sum = 0.0;
  for (int f = 0; f < hm.num_faces(); ++f) {
    const auto vs = hm.face_vertices(f);
    const int a = map.face_region[f] / 2, b1 = (a + 1) % 3, b2 = (a + 2) % 3;
    const Eigen::Vector3d e1 = hm.vertex_position(vs[1]) - hm.vertex_position(vs[0]);
    const Eigen::Vector3d e2 = hm.vertex_position(vs[2]) - hm.vertex_position(vs[0]);
    const Eigen::Vector3d normal = e1.cross(e2);
    const double area = 0.5 * normal.norm();
    if (!(area > 0.0)) continue;
    const Eigen::Vector3d x = e1.normalized(), y = normal.normalized().cross(x);
    Eigen::Matrix2d p, q;
    p << e1.dot(x), e2.dot(x), e1.dot(y), e2.dot(y);
    for (int k = 0; k < 2; ++k) {
      const int v = vs[k + 1];
      q(0, k) = (map.uvw(v, b1) - map.uvw(vs[0], b1)) * dims(b1);
      q(1, k) = (map.uvw(v, b2) - map.uvw(vs[0], b2)) * dims(b2);
    }
    const Eigen::Vector2d sigma = Eigen::JacobiSVD<Eigen::Matrix2d>(q * p.inverse()).singularValues();
    if (!(sigma(1) > 0.0)) return std::numeric_limits<double>::infinity();
    const double log_ratio = std::log(sigma(0) / sigma(1));
    sum += area * log_ratio * log_ratio;
    total += area;
  }
  return total > 0.0 ? std::sqrt(sum / total) : std::numeric_limits<double>::infinity();
}

// The cuboid layout: the user's corners, or among the automatic candidates (§3.3 cuboid corners)
// the one whose plain convex-combination surface map (§3.4.1, no area balancing) is least
// anisotropic, if clearly so (kLayoutAnisotropyMargin). A cuboid corner on a thin protrusion
// (bunny's ears), its three faces running up the protrusion, squeezes those faces into long
// strips where the fitted spline folds; the anisotropy tells such layouts apart cheaply.
polycube::CuboidLayout choose_layout(const mesh::HalfedgeMesh& hm, const Mesh2SplineOptions& options,
                                     const Progress& progress) {
  if (!options.corners.empty()) {
    polycube::CuboidLayoutOptions layout_options;
    layout_options.corners = options.corners;
    return polycube::compute_cuboid_layout(hm, layout_options, progress);
  }
  std::vector<polycube::CuboidLayout> layouts =
      polycube::candidate_cuboid_layouts(hm, kLayoutCandidates, job_share(progress, 0.0, 0.5));
  if (layouts.size() == 1) return std::move(layouts.front());
  std::size_t best = 0;
  double best_anisotropy = std::numeric_limits<double>::infinity(), first_anisotropy = best_anisotropy;
  param::CuboidSurfaceMapOptions map_options;  // mean-value weights: bijective on any valid mesh
  map_options.solver = param::SurfaceSolver::IncompleteCholesky;
  for (std::size_t k = 0; k < layouts.size(); ++k) {
    progress.report("cuboid layout", 0.5 + 0.5 * k / layouts.size());
    double anisotropy = std::numeric_limits<double>::infinity();
    try {
      const param::CuboidSurfaceMap map = param::compute_cuboid_surface_map(hm, layouts[k], map_options);
      anisotropy = surface_map_anisotropy(hm, map, cuboid_dims(hm, layouts[k]));
    } catch (const Error&) {
      // A candidate whose map fails (degenerate triangles) is not chosen; the job's own map
      // reports the problem if the first candidate is kept.
    }
    if (k == 0) first_anisotropy = anisotropy;
    if (anisotropy < best_anisotropy) {
      best_anisotropy = anisotropy;
      best = k;
    }
  }
  return std::move(layouts[first_anisotropy > best_anisotropy + kLayoutAnisotropyMargin ? best : 0]);
}

// Level 0 alone must fit the control point budget; checked before the volumetric grid (which
// grows with initial_cells³) is allocated.
void check_level0_budget(const Eigen::Vector3d& dims, const Mesh2SplineOptions& options, const std::string& name) {
  const std::array<int, 3> level0 = cells_for(dims, options.initial_cells);
  const long long level0_points = (level0[0] + 3LL) * (level0[1] + 3LL) * (level0[2] + 3LL);
  if (level0_points > options.max_control_points)
    throw Error("mesh '" + name + "': `initial_cells` = " + std::to_string(options.initial_cells) + " gives " +
                std::to_string(level0_points) + " control points at level 0, above `max_control_points` = " +
                std::to_string(options.max_control_points));
}

// The mesh vertices at their surface parameters, plus the face centroids of coarse meshes: they
// pin the spline between the vertices. Dense meshes need none (their vertices already sample
// every spline cell), and each sample costs (overlapping functions)² in the normal equations.
void add_mesh_samples(const mesh::HalfedgeMesh& hm, const param::CuboidSurfaceMap& surface_map,
                      std::vector<Eigen::Vector3d>& sample_uvw, std::vector<Eigen::Vector3d>& sample_xyz) {
  for (int v = 0; v < hm.num_vertices(); ++v) {
    if (hm.vertex_halfedge(v) == mesh::no_id) continue;
    sample_uvw.push_back(surface_map.uvw.row(v).transpose());
    sample_xyz.push_back(hm.vertex_position(v));
  }
  const bool add_centroids = static_cast<int>(sample_uvw.size()) < kDenseMeshVertices;
  for (int f = 0; add_centroids && f < hm.num_faces(); ++f) {
    const auto c = hm.face_vertices(f);
    sample_uvw.push_back((surface_map.uvw.row(c[0]) + surface_map.uvw.row(c[1]) + surface_map.uvw.row(c[2])).transpose() / 3.0);
    sample_xyz.push_back((hm.vertex_position(c[0]) + hm.vertex_position(c[1]) + hm.vertex_position(c[2])) / 3.0);
  }
}

// Grid fit: the nodes of the volumetric grid map (§3.4.2) as samples. Interior nodes of hexes
// still folded after the untangling are no valid targets: a fold-free spline cannot pass
// through them, so they are left to the fairing.
void add_grid_samples(const param::CuboidSurfaceLocator& locator, const std::array<int, 3>& nodes,
                      Mesh2SplineStats& stats, std::vector<Eigen::Vector3d>& sample_uvw,
                      std::vector<Eigen::Vector3d>& sample_xyz) {
  param::VolumetricGridOptions grid_options;
  grid_options.nodes = nodes;
  const param::VolumetricGridMap grid = param::compute_volumetric_grid_map(locator, grid_options);
  stats.grid_inverted_hexes = grid.num_inverted_hexes;
  stats.grid_min_scaled_jacobian = grid.min_scaled_jacobian;
  std::vector<char> folded(grid.xyz.rows(), 0);
  for (int k = 0; k + 1 < nodes[2] && grid.num_inverted_hexes > 0; ++k)
    for (int j = 0; j + 1 < nodes[1]; ++j)
      for (int i = 0; i + 1 < nodes[0]; ++i) {
        std::array<Eigen::Vector3d, 8> corners;
        std::array<int, 8> ids;
        for (int c = 0; c < 8; ++c) {
          ids[c] = param::grid_node_index(nodes, i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          corners[c] = grid.xyz.row(ids[c]).transpose();
        }
        if (mesh::hex_min_scaled_jacobian(corners) <= 0.0)
          for (int id : ids) folded[id] = 1;
      }
  for (int k = 0; k < nodes[2]; ++k)
    for (int j = 0; j < nodes[1]; ++j)
      for (int i = 0; i < nodes[0]; ++i) {
        const bool boundary = i == 0 || j == 0 || k == 0 || i == nodes[0] - 1 || j == nodes[1] - 1 || k == nodes[2] - 1;
        if (folded[param::grid_node_index(nodes, i, j, k)] && !boundary) continue;
        sample_uvw.emplace_back(double(i) / (nodes[0] - 1), double(j) / (nodes[1] - 1), double(k) / (nodes[2] - 1));
        sample_xyz.push_back(grid.xyz.row(param::grid_node_index(nodes, i, j, k)).transpose());
      }
}

// Meshless fit (§4.3.2): the boundary nodes of the same lattice, located on the surface map.
void add_boundary_lattice_samples(const param::CuboidSurfaceLocator& locator, const std::array<int, 3>& nodes,
                                  std::vector<Eigen::Vector3d>& sample_uvw, std::vector<Eigen::Vector3d>& sample_xyz) {
  for (int face = 0; face < polycube::num_cube_faces; ++face) {
    const int a = face / 2;
    const int ns = nodes[(a + 1) % 3], nt = nodes[(a + 2) % 3];
    for (int j = 0; j < nt; ++j)
      for (int i = 0; i < ns; ++i) {
        const double s = double(i) / (ns - 1), t = double(j) / (nt - 1);
        sample_uvw.push_back(polycube::cube_face_point(face, s, t));
        sample_xyz.push_back(locator.locate(face, s, t));
      }
  }
}

// The fit's rms_rel and max_rel from the per-sample errors.
void set_fit_errors(const Eigen::VectorXd& errors, double diagonal, Mesh2SplineStats& stats) {
  stats.rms_rel = rms(errors) / diagonal;
  stats.max_rel = errors.size() ? errors.maxCoeff() / diagonal : 0.0;
}

// The boundary layer folds where refined boundary cells hold no interior samples (the grid is
// coarser than the surface's concave detail): unfold it with the interior control points only,
// so the boundary and its surface fit stay exactly as they are.
void untangle_fit(spline::TSpline& ts, const Samples& samples, double diagonal, const Progress& progress,
                  Mesh2SplineStats& stats) {
  progress.report("untangle", 0.7);
  // From here on the control points change only a few at a time (incremental cell updates)
  // while the untangler and the measures evaluate whole lattices: per-cell polynomials pay.
  ts.use_cell_polynomials();
  // The untangler's passes report within the job's untangle share and honour cancellation.
  const spline::SplineUntangleResult untangled =
      spline::untangle_spline(ts, samples.uvw, samples.xyz, {}, job_share(progress, 0.7, 0.75));
  stats.negative_jacobian_fraction_fit = double(untangled.initial_negative) / untangled.scanned;
  stats.untangled_control_points = untangled.free_functions;
  stats.creased_control_points = untangled.crease_functions;
  if (untangled.free_functions > 0 || untangled.crease_functions > 0)
    set_fit_errors(sample_errors(ts, samples), diagonal, stats);
}

// Optional: the Gauss–Newton repair towards a minimum scaled Jacobian.
void repair_fit(spline::TSpline& ts, const Samples& samples, double diagonal, const Mesh2SplineOptions& options,
                const Progress& progress, Mesh2SplineStats& stats) {
  progress.report("Jacobian repair", 0.7);
  spline::JacobianRepairOptions repair_options;
  repair_options.min_scaled_jacobian = options.min_scaled_jacobian;
  const spline::JacobianRepairResult repair = spline::repair_jacobian(ts, repair_options);
  if (options.untangle == Mesh2SplineOptions::Untangle::Off)
    stats.negative_jacobian_fraction_fit = double(repair.initial_negative) / repair.points;
  stats.repaired_control_points = repair.moved_points;
  set_fit_errors(sample_errors(ts, samples), diagonal, stats);
}

// The measures of DESIGN.md (measure_mesh2spline) and the Bernstein certificate of det J on every
// cell (DESIGN §6, the headline validity measure).
void measure(const spline::TSpline& ts, const mesh::HalfedgeMesh& hm, const param::CuboidSurfaceMap& surface_map,
             const spline::RefinementGrid& refinement, double diagonal, const Mesh2SplineOptions& options,
             const Progress& progress, StageTimer& timer, Mesh2SplineStats& stats) {
  progress.report("measures", 0.75);
  Mesh2SplineMeasureOptions measure_options;
  measure_options.surface_samples = options.measure_samples;
  measure_options.seed = options.seed;
  const Mesh2SplineMeasureResult measures =
      measure_mesh2spline(ts, hm, surface_map.uvw, refinement, diagonal, measure_options);
  stats.hausdorff_rel = measures.hausdorff_rel;
  stats.rms_geo_rel = measures.rms_geo_rel;
  stats.min_scaled_jacobian = measures.min_scaled_jacobian;
  stats.negative_jacobian_fraction = measures.negative_jacobian_fraction;
  stats.jacobian_samples = measures.jacobian_samples;
  if (options.min_scaled_jacobian == 0.0 && options.untangle == Mesh2SplineOptions::Untangle::Off)
    stats.negative_jacobian_fraction_fit = stats.negative_jacobian_fraction;
  stats.semi_standard_max_error = measures.semi_standard_max_error;
  timer.end_stage("measures");

  progress.report("certificate", 0.8);
  record_certificate(stats, spline::certify_jacobian(ts));
  timer.end_stage("certificate");
}

// The smallest uniform grid (same aspect as the cuboid) whose fit reaches the T-spline's rms:
// doubling from initial_cells, then bisection (stats uniform_control_points, uniform_rms_rel).
void compare_uniform(const Eigen::Vector3d& dims, const param::CuboidSurfaceLocator& locator, const Samples& samples,
                     const Mesh2SplineOptions& options, int longest_nodes, double diagonal, Mesh2SplineStats& stats) {
  auto uniform_rms = [&](int n, int* points) {
    spline::TSpline u = uniform_tspline(cells_for(dims, n));
    const Eigen::MatrixX3d p = greville_prior(u, locator);
    u.set_points(p);
    fit(u, samples, p, options, longest_nodes);
    *points = u.num_functions();
    return rms(sample_errors(u, samples)) / diagonal;
  };
  int lo_n = options.initial_cells, hi_n = -1, points = 0;
  double hi_rms = 0.0;
  for (int n = options.initial_cells; n <= 64; n *= 2) {
    const double r = uniform_rms(n, &points);
    if (r <= stats.rms_rel) {
      hi_n = n;
      hi_rms = r;
      break;
    }
    lo_n = n;
    if (points > 8 * options.max_control_points) break;
  }
  if (hi_n <= 0) return;
  while (hi_n - lo_n > 1) {
    const int mid = (lo_n + hi_n) / 2;
    const double r = uniform_rms(mid, &points);
    if (r <= stats.rms_rel) {
      hi_n = mid;
      hi_rms = r;
    } else {
      lo_n = mid;
    }
  }
  stats.uniform_control_points = uniform_tspline(cells_for(dims, hi_n)).num_functions();
  stats.uniform_rms_rel = hi_rms;
}

}  // namespace

void record_certificate(Mesh2SplineStats& stats, spline::JacobianCertificate certificate) {
  stats.jacobian_certified_fraction = certificate.jacobian_certified_fraction;
  stats.det_j_lower_bound_rel = certificate.det_j_lower_bound_rel;
  stats.certificate_cells = certificate.cells;
  stats.uncertified_cells = std::move(certificate.uncertified);
}

Mesh2SplineResult run_mesh2spline(const mesh::TriangleMesh& input, const std::string& name,
                                  const Mesh2SplineOptions& options, const Progress& progress) {
  check_options(options);
  Mesh2SplineStats stats;
  StageTimer timer(stats.times_s);

  progress.report("validate", 0.0);
  // Every stage works in a unit box (centred, longest side in [0.5, 1)): absolute tolerances
  // then mean the same for any position and unit; the spline is mapped back at the end.
  const mesh::UnitBox box = mesh::unit_box_of(input, name);
  const mesh::HalfedgeMesh hm = validated_mesh(box.to_unit(input), name, job_share(progress, 0.0, 0.05));
  const double diagonal = bbox_diagonal(hm, name);
  timer.end_stage("validate");

  progress.report("cuboid layout", 0.05);
  const polycube::CuboidLayout layout = choose_layout(hm, options, job_share(progress, 0.05, 0.1));
  std::copy(layout.corners.begin(), layout.corners.end(), stats.corners.begin());
  stats.min_corner_distance_rel = layout.min_corner_distance_rel;
  const Eigen::Vector3d dims = cuboid_dims(hm, layout);
  check_level0_budget(dims, options, name);
  timer.end_stage("layout");

  progress.report("surface map", 0.1);
  param::CuboidSurfaceMapOptions map_options;
  map_options.weights = options.weights;
  map_options.area_balance_iterations = options.area_balance_iterations;
  map_options.squeezed_below = options.squeezed_below;
  // IC(0) and full-accuracy balancing rounds keep this job's outputs and measured figures
  // (README) as they are; on its meshes (tens of thousands of vertices) the savings are small.
  map_options.solver = param::SurfaceSolver::IncompleteCholesky;
  map_options.balance_tolerance = map_options.tolerance;
  const param::CuboidSurfaceMap surface_map = param::compute_cuboid_surface_map(hm, layout, map_options, job_share(progress, 0.1, 0.2));
  stats.flipped_triangles = surface_map.num_flipped;
  stats.squeeze_rounds = surface_map.squeeze_rounds;
  stats.surface_least_density = surface_map.least_density;
  if (options.squeezed == Mesh2SplineOptions::Squeezed::Refuse &&
      param::squeezed_map(surface_map.squeeze_rounds, surface_map.least_density, options.squeezed_below)) {
    char density[96];
    std::snprintf(density, sizeof density, "least density %.3g against squeezed_below %.3g",
                  surface_map.least_density, options.squeezed_below);
    throw SqueezedOneCuboid("mesh '" + name + "': its one-cuboid surface map is squeezed (" +
                                std::to_string(surface_map.squeeze_rounds) + " rescue rounds, " + density +
                                "): a limb or tip crowds into a spot of a cube face",
                            surface_map.squeeze_rounds);
  }
  const param::CuboidSurfaceLocator locator(hm, surface_map);
  timer.end_stage("surface_map");

  // Samples: mesh vertices at their surface parameters, the lattice of the volumetric grid
  // (all nodes for the grid fit, boundary nodes for the meshless fit).
  progress.report("volumetric map", 0.2);
  const int longest_nodes = options.grid_nodes > 0 ? options.grid_nodes : std::max(17, 4 * options.initial_cells + 1);
  std::array<int, 3> nodes;
  for (int a = 0; a < 3; ++a)
    nodes[a] = std::max(5, static_cast<int>(std::lround((longest_nodes - 1) * dims(a) / dims.maxCoeff())) + 1);
  std::vector<Eigen::Vector3d> sample_uvw, sample_xyz;
  add_mesh_samples(hm, surface_map, sample_uvw, sample_xyz);
  if (options.fit == Mesh2SplineFit::Grid)
    add_grid_samples(locator, nodes, stats, sample_uvw, sample_xyz);
  else
    add_boundary_lattice_samples(locator, nodes, sample_uvw, sample_xyz);
  // §4.3.1 boundary restricted control grid, refined by run_hierarchical_fitting below.
  const std::array<int, 3> cells = cells_for(dims, options.initial_cells);
  spline::RefinementGrid refinement(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), cells);
  for (int leaf : refinement.leaves())
    add_cell_surface_samples(locator, refinement.cell_min(leaf), refinement.cell_max(leaf), 2, sample_uvw, sample_xyz);
  timer.end_stage("volumetric_map");

  progress.report("fit", 0.3);
  SolidFit solid(uniform_tspline(cells), std::move(refinement), locator, options, longest_nodes, diagonal,
                 std::move(sample_uvw), std::move(sample_xyz), stats, timer, progress);
  spline::run_hierarchical_fitting(solid, solid);
  spline::TSpline ts = std::move(solid.ts);
  refinement = std::move(solid.refinement);
  const Samples samples = std::move(solid.samples);
  stats.control_points = ts.num_functions();
  stats.samples = static_cast<int>(samples.uvw.rows());
  set_fit_errors(solid.errors, diagonal, stats);

  if (options.untangle == Mesh2SplineOptions::Untangle::On) {
    untangle_fit(ts, samples, diagonal, progress, stats);
    timer.end_stage("untangle");
  }
  if (options.min_scaled_jacobian > 0.0) {
    repair_fit(ts, samples, diagonal, options, progress, stats);
    timer.end_stage("jacobian_repair");
  }
  measure(ts, hm, surface_map, refinement, diagonal, options, progress, timer, stats);
  if (options.compare_uniform == Mesh2SplineOptions::CompareUniform::On) {
    progress.report("uniform comparison", 0.85);
    compare_uniform(dims, locator, samples, options, longest_nodes, diagonal, stats);
    timer.end_stage("uniform_comparison");
  }
  ts.set_points(box.from_unit_points(ts.points()));
  progress.report("done", 1.0);
  return Mesh2SplineResult{std::move(ts), std::move(stats)};
}

}  // namespace volspline::pipeline
