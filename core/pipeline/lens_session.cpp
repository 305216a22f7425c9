// SPDX-License-Identifier: MIT
#include "core/pipeline/lens_session.h"

#include <algorithm>
#include <numeric>
#include <chrono>
#include <cmath>
#include <deque>
#include <memory>
#include <optional>

#include <Eigen/Geometry>

#include "core/common/error.h"
#include "core/lens/baseline_lens.h"
#include "core/lens/lens_flattener.h"
#include "core/lens/lens_measures.h"
#include "core/lens/lens_mesh.h"
#include "core/lens/lens_texture.h"
#include "core/lens/rasterize.h"
#include "core/lens/roi_field.h"
#include "core/lens/roi_translation.h"

namespace volspline::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Radius (texture pixels) around a ROI centre over which the magnification is measured.
double measure_radius(const lens::RoiField& roi) { return 0.15 * roi.inscribed_radius(); }

// Grid resolution of the h0 search: coarse enough to be cheap, fine enough to resolve the centre.
constexpr int kCalibrationGrid = 48;
// A metric lens that measures more than this fraction below the request is reported as limited.
constexpr double kLimitedTolRel = 0.03;

// Final-grid magnification error (relative) above which the coarse h0 gets one secant correction.
constexpr double kCalibrationTolRel = 0.03;

struct Deformation {
  Eigen::MatrixX2d positions, texture;
  mesh::Triangles triangles, grid_triangles;
  int iterations = 0;
  bool converged = true;
  double ms_mesh = 0, ms_factorize = 0, ms_iterations = 0;
};

// What a metric run needs besides the ROI fields and options to share a lens mesh.
struct MeshKey {
  int width = 0, height = 0, grid = 0;
  double h0 = 0, band = 0;
  std::vector<double> height_scale;  // per ROI, relative to h0 (empty: 1 each)
  LensBoundary boundary = LensBoundary::Pinned;
  std::vector<lens::Roi> rois;
};

bool same_rois(const std::vector<lens::Roi>& a, const std::vector<lens::Roi>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const lens::Roi &x = a[i], &y = b[i];
    if (x.shape != y.shape || x.values != y.values || x.mask.width != y.mask.width || x.mask.height != y.mask.height ||
        x.mask.channels != y.mask.channels || x.mask.pixels != y.mask.pixels)
      return false;
  }
  return true;
}

bool same_mesh(const MeshKey& a, const MeshKey& b) {
  return a.width == b.width && a.height == b.height && a.grid == b.grid && a.h0 == b.h0 && a.band == b.band &&
         a.height_scale == b.height_scale && a.boundary == b.boundary && same_rois(a.rois, b.rois);
}

// A lens mesh ready to flatten: texture, start positions and the factorized Eq. 6.3 matrix.
struct PreparedMesh {
  MeshKey key;
  Eigen::MatrixX2d texture, start;
  mesh::Triangles triangles, grid_triangles;
  double scale = 1.0;
  Eigen::RowVector2d mid;
  lens::LensFlattener flattener;
  double ms_mesh = 0;
};

// The options of a metric request that decide its final h0 (calibration and fold-free search).
struct CalibrationKey {
  MeshKey mesh;  // h0 unused
  double magnification = 0, height = 0, alpha = 0, tol_rel = 0;
  int max_iterations = 0;
  double h0 = 0;  // the answer, with each ROI's height relative to it
  std::vector<double> height_scale;
};

bool same_calibration(const CalibrationKey& a, const CalibrationKey& b) {
  return same_mesh(a.mesh, b.mesh) && a.magnification == b.magnification && a.height == b.height &&
         a.alpha == b.alpha && a.tol_rel == b.tol_rel && a.max_iterations == b.max_iterations;
}

// Cache bounds: a handful of meshes (calibration visits 3–6 heights), and at most this many
// vertices in total so a 2000-grid run does not pin hundreds of MB (the newest mesh is always kept).
constexpr std::size_t kMaxMeshes = 8;
constexpr long long kMaxCachedVertices = 1500000;
constexpr std::size_t kMaxCalibrations = 16;

std::shared_ptr<const PreparedMesh> prepare_mesh(const std::vector<lens::RoiField>& rois, const MeshKey& key) {
  auto p = std::make_shared<PreparedMesh>();
  p->key = key;
  const auto t_mesh = Clock::now();
  lens::LensMeshOptions mesh_options;
  mesh_options.grid = key.grid;
  mesh_options.height_rel = key.h0;
  mesh_options.height_scale = key.height_scale;
  mesh_options.band_rel = key.band;
  mesh_options.pin_context = key.boundary == LensBoundary::Pinned ? lens::LensMeshOptions::PinContext::On
                                                                  : lens::LensMeshOptions::PinContext::Off;
  const lens::LensMesh lens_mesh = lens::build_lens_mesh(rois, key.width, key.height, mesh_options);
  p->texture = lens::harmonic_texture(lens_mesh);
  p->ms_mesh = ms_since(t_mesh);

  p->start = lens_mesh.xyz.leftCols<2>();
  p->mid = Eigen::RowVector2d(0.5 * key.width, 0.5 * key.height);
  if (key.boundary == LensBoundary::Square) {
    // §6.4 boundary control: the border sits on the square scaled by √(A_lens/A_image).
    double area = 0;
    for (int t = 0; t < lens_mesh.triangles.rows(); ++t) {
      const Eigen::Vector3d a = lens_mesh.xyz.row(lens_mesh.triangles(t, 0));
      const Eigen::Vector3d b = lens_mesh.xyz.row(lens_mesh.triangles(t, 1));
      const Eigen::Vector3d c = lens_mesh.xyz.row(lens_mesh.triangles(t, 2));
      area += 0.5 * (b - a).cross(c - a).norm();
    }
    p->scale = std::sqrt(area / (double(key.width) * key.height));
    for (int v = 0; v < p->start.rows(); ++v) p->start.row(v) = p->mid + p->scale * (p->start.row(v) - p->mid);
  }
  // §6.4 weights (1 + h_k)·A_k·cotθ with h_k the mean z in pixels, as printed: the raised focus then
  // outweighs the flat context, which absorbs the transition (normalizing h by the image size made
  // (1 + h) ≈ 1 and left the distortion inside the focus).
  p->flattener.compute(lens_mesh.xyz, lens_mesh.triangles, lens_mesh.pinned, 1.0);
  p->triangles = lens_mesh.triangles;
  p->grid_triangles = lens_mesh.grid_triangles;
  return p;
}

// Iterations of Algorithm 5 on a prepared mesh (the only per-α work).
Deformation flatten_prepared(const PreparedMesh& p, bool built, const LensOptions& options, const Progress& progress) {
  lens::FlattenOptions flatten_options;
  flatten_options.alpha = options.alpha;
  flatten_options.tol_rel = options.tol_rel;
  flatten_options.max_iterations = options.max_iterations;
  lens::FlattenResult flat = p.flattener.flatten(p.start, flatten_options, progress);
  if (p.scale != 1.0)
    for (int v = 0; v < flat.positions.rows(); ++v)
      flat.positions.row(v) = p.mid + (flat.positions.row(v) - p.mid) / p.scale;
  Deformation d;
  d.positions = std::move(flat.positions);
  d.texture = p.texture;
  d.triangles = p.triangles;
  d.grid_triangles = p.grid_triangles;
  d.iterations = flat.iterations;
  d.converged = flat.converged;
  d.ms_mesh = built ? p.ms_mesh : 0.0;
  d.ms_factorize = built ? flat.ms_factorize : 0.0;
  d.ms_iterations = flat.ms_iterations;
  return d;
}

// Flipped triangles of the whole exported mesh, grid and ROI-adapted triangles alike, measured
// against the texture's orientation (lens_measures.h).
int flipped(const Deformation& d) { return lens::count_flipped_triangles(d.positions, d.texture, d.triangles); }

std::vector<double> magnifications(const Deformation& d, const std::vector<lens::RoiField>& rois) {
  std::vector<double> out;
  for (const lens::RoiField& roi : rois)
    out.push_back(lens::measure_magnification(d.positions, d.texture, d.grid_triangles, roi.centre(), measure_radius(roi)));
  return out;
}

// Per-ROI height scales: `scale`, or 1 each if it is empty.
std::vector<double> scales_per_roi(const std::vector<double>& scale, std::size_t num_rois) {
  return scale.empty() ? std::vector<double>(num_rois, 1.0) : scale;
}

double mean(const std::vector<double>& values) {
  double s = 0;
  for (double v : values) s += v;
  return values.empty() ? 0.0 : s / values.size();
}

// Secant search in log–log space for the parameter whose measured magnification is the target;
// the relation is monotone increasing. Returns the best parameter found and the last log–log slope.
struct SearchResult {
  double parameter = 1.0;
  double slope = 1.0;
};
template <class Measure>
SearchResult search_parameter(Measure measure, double target, double p0, double p1, int max_steps, double tol_rel) {
  double lp0 = std::log(p0), lp1 = std::log(p1);
  double lm0 = std::log(std::max(measure(p0), 1e-6)), lm1 = std::log(std::max(measure(p1), 1e-6));
  const double lt = std::log(target);
  double best = std::abs(lm0 - lt) < std::abs(lm1 - lt) ? p0 : p1;
  double best_err = std::min(std::abs(lm0 - lt), std::abs(lm1 - lt));
  double slope = 1.0;
  for (int step = 0; step < max_steps && best_err > tol_rel; ++step) {
    slope = (lm1 - lm0) / (lp1 - lp0);
    if (!(slope > 1e-3)) slope = 1e-3;
    const double lp2 = std::clamp(lp1 + (lt - lm1) / slope, lp1 - 2.0, lp1 + 2.0);
    const double lm2 = std::log(std::max(measure(std::exp(lp2)), 1e-6));
    lp0 = lp1, lm0 = lm1, lp1 = lp2, lm1 = lm2;
    if (std::abs(lm2 - lt) < best_err) best_err = std::abs(lm2 - lt), best = std::exp(lp2);
  }
  return {best, slope};
}

// The last solved metric run with the pinned boundary and the lens clear of the image border: what
// a LensMode::Live request may translate.
struct TranslationBase {
  int width = 0, height = 0;
  LensOptions options;  // as requested (height may be 0: calibrated)
  std::vector<lens::Roi> rois;
  LensResult result;  // positions, texture, triangles and stats; no image
};

// Every option that shapes a metric deformation, the height aside (render and mode do not).
bool same_deformation_options(const LensOptions& a, const LensOptions& b) {
  return a.method == b.method && a.magnification == b.magnification && a.alpha == b.alpha && a.grid == b.grid &&
         a.boundary == b.boundary && a.band == b.band && a.tol_rel == b.tol_rel && a.max_iterations == b.max_iterations;
}

// True if every ROI's lens and context band (the free vertices of §6.3.1 with pinned context) stay
// at least one grid cell and a half inside the image: the pinned border then plays no part, so the
// flattening does not change when the ROIs move, apart from where the grid samples the lens.
bool lens_clear_of_border(const std::vector<lens::Roi>& rois, const std::vector<lens::RoiField>& fields, int width,
                          int height, int grid, double band) {
  const double margin = 1.5 * double(std::max(width, height)) / (grid - 1);
  for (std::size_t i = 0; i < rois.size(); ++i) {
    const lens::PixelBox box = lens::roi_reach_box(rois[i], band * fields[i].equivalent_radius());
    if (box.x0 < margin || box.y0 < margin || box.x1 > width - margin || box.y1 > height - margin) return false;
  }
  return true;
}

// LensMode::Live: the base run's deformation moved by `offset`. Pinned vertices keep position =
// texture, so moving both moves the lens and leaves the context the identity; pixels the moved mesh
// uncovers render as the identity too. Eq. 6.9 and the magnification are translation invariant, so
// the base's stats stand (timings apart: ms_total is left to the caller).
LensResult translated(const TranslationBase& base, const Eigen::Vector2d& offset, const LensInput& input,
                      const LensOptions& options, const Progress& progress) {
  LensResult result;
  result.positions = base.result.positions.rowwise() + offset.transpose();
  result.texture = base.result.texture.rowwise() + offset.transpose();
  result.triangles = base.result.triangles;
  result.stats = base.result.stats;
  LensStats& s = result.stats;
  s.translated = true;
  s.ms_calibration = s.ms_mesh = s.ms_factorize = s.ms_per_iteration = s.ms_render = 0;
  if (options.render == LensOptions::Render::On) {
    progress.report("render", 0.0);
    const auto t_render = Clock::now();
    result.image = lens::render_textured_mesh(input.image, result.positions, result.texture, result.triangles,
                                              input.image.width, input.image.height);
    s.ms_render = ms_since(t_render);
  }
  progress.report("done", 1.0);
  return result;
}

void validate(const LensInput& input, const LensOptions& o) {
  const auto bad = [](const std::string& what) { throw Error(what); };
  if (input.image.width <= 0 || input.image.height <= 0 || input.image.channels < 1 || input.image.channels > 4 ||
      input.image.pixels.size() != std::size_t(input.image.width) * input.image.height * input.image.channels)
    bad("'" + input.name + "': empty or malformed image");
  if (input.image.width < 2 || input.image.height < 2) bad("'" + input.name + "': image must be at least 2x2 pixels");
  if (input.rois.empty()) bad("lens: at least one ROI is needed (`rois`)");
  if (!(o.magnification > 1.0)) bad("lens: magnification must be > 1, got " + std::to_string(o.magnification));
  if (!(o.magnification <= 16.0)) bad("lens: magnification must be at most 16, got " + std::to_string(o.magnification));
  if (!(o.height >= 0.0 && o.height <= 50.0)) bad("lens: height must be in (0, 50] ROI radii, got " + std::to_string(o.height));
  if (!(o.alpha >= 0.0 && o.alpha <= 1.0)) bad("lens: alpha must be in [0, 1], got " + std::to_string(o.alpha));
  if (o.grid < 4) bad("lens: grid must be at least 4, got " + std::to_string(o.grid));
  if (o.grid > 2000) bad("lens: grid must be at most 2000, got " + std::to_string(o.grid));
  if (!(o.band > 0.0 && o.band <= 10.0)) bad("lens: band must be in (0, 10], got " + std::to_string(o.band));
  if (!(o.tol_rel > 0.0 && o.tol_rel < 1.0)) bad("lens: tol_rel must be in (0, 1), got " + std::to_string(o.tol_rel));
  if (o.max_iterations < 1 || o.max_iterations > 100000)
    bad("lens: max_iterations must be in [1, 100000], got " + std::to_string(o.max_iterations));
  if (!o.height_scale.empty() && o.height_scale.size() != input.rois.size())
    bad("lens: `height_scale` needs one entry per ROI (" + std::to_string(input.rois.size()) + "), got " +
        std::to_string(o.height_scale.size()));
  for (double x : o.height_scale)
    if (!(x > 0.0 && x <= 10.0)) bad("lens: `height_scale` entries must be in (0, 10], got " + std::to_string(x));
  for (const lens::Roi& roi : input.rois) lens::validate_roi(roi, input.image.width, input.image.height);
}

// A metric run on the full grid at height h, lowered until the flattening is fold-free: thesis
// §6.5 repairs rare fold-overs with [77]; we lower h0 (×0.8, at most 6 times) instead. h: in, the
// height to try; out, the height of the returned run.
template <class RunAt>
Deformation fold_free_run(RunAt&& run_at, const LensOptions& options, double& h, const Progress& progress) {
  Deformation out = run_at(options.grid, h, progress);
  for (int attempt = 0; attempt < 6; ++attempt) {
    if (flipped(out) == 0) break;
    h *= 0.8;
    out = run_at(options.grid, h, progress);
  }
  return out;
}

// The h0 of the requested magnification: a 1-D secant on a coarse grid (3–5 cheap runs), not the
// whole pipeline at full size. A folding height counts as overshoot, so the search settles on the
// tallest clean lens.
template <class RunAt>
SearchResult coarse_height_search(RunAt&& run_at, const std::vector<lens::RoiField>& rois, const LensOptions& options) {
  const Progress quiet;
  const int coarse = std::min(options.grid, kCalibrationGrid);
  const auto measure = [&](double h) {
    const Deformation trial = run_at(coarse, h, quiet);
    return flipped(trial) > 0 ? 4.0 * options.magnification : mean(magnifications(trial, rois));
  };
  return search_parameter(measure, options.magnification, 1.0, 1.4, 3, 0.01);
}

// The coarse grid resolves the centre less well: one secant step on the final grid with the
// coarse slope, kept (d and h0 replaced) only if it lands closer to the request.
template <class RunAt>
void refine_on_final_grid(RunAt&& run_at, const std::vector<lens::RoiField>& rois, const LensOptions& options,
                          double calibration_slope, const Progress& progress, Deformation& d, double& h0, LensStats& s) {
  const double lt = std::log(options.magnification);
  const double error = lt - std::log(std::max(mean(magnifications(d, rois)), 1e-6));
  if (std::abs(error) <= kCalibrationTolRel) return;
  const auto t_fix = Clock::now();
  double h1 = h0 * std::exp(std::clamp(error / std::clamp(calibration_slope, 0.2, 5.0), -1.0, 1.0));
  Deformation retry = fold_free_run(run_at, options, h1, progress);
  if (std::abs(lt - std::log(std::max(mean(magnifications(retry, rois)), 1e-6))) < std::abs(error)) {
    d = std::move(retry);
    h0 = h1;
  }
  s.ms_calibration += ms_since(t_fix);
}

// Several ROIs share h0, but at one height an elongated ROI (a ridge-shaped lens) magnifies less
// than a round one: each ROI's height gets its own log–log secant steps toward the request, as far
// as it goes without a fold (first step with slope 1, the
// per-ROI slope measured on camera.png for circles and rectangles being 0.8–1.1; then each ROI's
// own secant). A step that folds is halved for the lenses it raised. At most kEqualizeRuns runs;
// a fold-free run replaces the kept one if no lens lies farther from the request (beyond the
// calibration tolerance) and the lenses lie closer in sum. `scale` (per ROI, relative to
// h0, empty: 1 each) is what run_at builds with; the largest is kept at 1, so h0 stays the
// tallest lens's height.
template <class RunAt>
void equalize_lenses(RunAt&& run_at, const std::vector<lens::RoiField>& rois, const LensOptions& options,
                     const Progress& progress, Deformation& d, double& h0, std::vector<double>& scale, LensStats& s) {
  constexpr int kEqualizeRuns = 5;
  const auto t_equalize = Clock::now();
  const auto log_of = [](double m) { return std::log(std::max(m, 1e-6)); };
  const std::size_t n = rois.size();
  const std::vector<double> m0 = magnifications(d, rois);
  const double lt = std::log(options.magnification);
  const auto errors = [&](const std::vector<double>& m) {
    std::vector<double> e(m.size());
    for (std::size_t i = 0; i < m.size(); ++i) e[i] = std::abs(lt - log_of(m[i]));
    return e;
  };
  const auto sum = [](const std::vector<double>& e) { return std::accumulate(e.begin(), e.end(), 0.0); };
  // Better: no lens moves farther from the request (beyond the calibration tolerance), the sum closer.
  const auto better = [&](const std::vector<double>& e, const std::vector<double>& best) {
    for (std::size_t i = 0; i < e.size(); ++i)
      if (e[i] > std::max(best[i], kCalibrationTolRel)) return false;
    return sum(e) < sum(best);
  };
  std::vector<double> best_error = errors(m0);
  std::vector<double> best_scale = scales_per_roi(scale, n), slope(n, 1.0), lh(n), lm(n);
  for (std::size_t i = 0; i < n; ++i) lh[i] = std::log(h0 * best_scale[i]), lm[i] = log_of(m0[i]);
  std::vector<double> next(n);
  for (std::size_t i = 0; i < n; ++i) next[i] = lh[i] + std::clamp((lt - lm[i]) / slope[i], -0.7, 0.7);
  for (int run = 0; run < kEqualizeRuns && *std::max_element(best_error.begin(), best_error.end()) > kCalibrationTolRel; ++run) {
    const double tallest = *std::max_element(next.begin(), next.end());
    const double h = std::exp(tallest);
    scale.resize(n);
    for (std::size_t i = 0; i < n; ++i) scale[i] = std::exp(next[i] - tallest);
    Deformation trial = run_at(options.grid, h, progress);
    if (flipped(trial) > 0) {
      for (std::size_t i = 0; i < n; ++i)
        if (next[i] > lh[i]) next[i] = lh[i] + 0.5 * (next[i] - lh[i]);
      continue;
    }
    const std::vector<double> m = magnifications(trial, rois);
    for (std::size_t i = 0; i < n; ++i) {
      if (std::abs(next[i] - lh[i]) > 1e-3) slope[i] = std::clamp((log_of(m[i]) - lm[i]) / (next[i] - lh[i]), 0.2, 5.0);
      lh[i] = next[i], lm[i] = log_of(m[i]);
      next[i] = lh[i] + std::clamp((lt - lm[i]) / slope[i], -0.7, 0.7);
    }
    if (better(errors(m), best_error)) {
      best_error = errors(m);
      best_scale = scale;
      d = std::move(trial);
      h0 = h;
    }
  }
  scale = best_scale;
  s.ms_calibration += ms_since(t_equalize);
}

// A baseline lens (fisheye, bifocal, zoom) on the plain grid, its parameter searched so that the
// measured magnification is the request (s.baseline_parameter).
Deformation baseline_deformation(const std::vector<lens::RoiField>& rois, const LensOptions& options, int width,
                                 int height, LensStats& s) {
  Deformation d;
  const lens::LensMesh grid = lens::build_grid(width, height, options.grid);
  d.texture = grid.xyz.leftCols<2>();
  d.triangles = grid.triangles;
  d.grid_triangles = grid.grid_triangles;
  std::vector<lens::RadialLens> lenses;
  for (const lens::RoiField& roi : rois) {
    // Baselines are radial: a disc of the ROI's area at its centre, free out to the same band.
    lenses.push_back({roi.centre(), roi.equivalent_radius(), (1.0 + options.band) * roi.equivalent_radius()});
  }
  const lens::BaselineKind kind = options.method == LensMethod::Fisheye   ? lens::BaselineKind::Fisheye
                                  : options.method == LensMethod::Bifocal ? lens::BaselineKind::Bifocal
                                                                          : lens::BaselineKind::Zoom;
  const auto measure = [&](double m) {
    Deformation trial = d;
    trial.positions = lens::baseline_positions(kind, d.texture, lenses, std::max(m, 1.0 + 1e-9));
    return mean(magnifications(trial, rois));
  };
  const double m = search_parameter(measure, options.magnification, options.magnification,
                                    options.magnification * 1.1, 12, 0.002).parameter;
  d.positions = lens::baseline_positions(kind, d.texture, lenses, m);
  s.baseline_parameter = m;
  return d;
}

// The measures of a deformation (Eq. 6.9 over the whole image and the focus, magnification,
// fold-overs) and its counts and timings into s.
void measure_deformation(const Deformation& d, const std::vector<lens::RoiField>& rois, const LensOptions& options,
                         LensStats& s) {
  s.magnification_per_roi = magnifications(d, rois);
  s.magnification_center = mean(s.magnification_per_roi);
  const int grid_vertices = static_cast<int>(d.grid_triangles.maxCoeff()) + 1;
  // Focus: grid triangles whose content (texture centroid) lies inside a ROI; the rest is the
  // transition and the context. The whole-image numbers stay the headline.
  std::vector<char> focus(static_cast<std::size_t>(d.grid_triangles.rows()), 0);
  for (int t = 0; t < d.grid_triangles.rows(); ++t) {
    const Eigen::Vector2d c = (d.texture.row(d.grid_triangles(t, 0)) + d.texture.row(d.grid_triangles(t, 1)) +
                               d.texture.row(d.grid_triangles(t, 2))).transpose() / 3.0;
    for (const lens::RoiField& roi : rois) focus[t] = focus[t] || roi.axis_distance(c.x(), c.y()) < 1.0;
  }
  const lens::ShapeDistortion distortion = lens::measure_distortion(
      d.positions.topRows(grid_vertices), d.texture.topRows(grid_vertices), d.grid_triangles, focus);
  s.distortion_sum = distortion.sum;
  s.distortion_max = distortion.max;
  s.distortion_sum_focus = distortion.sum_focus;
  s.distortion_max_focus = distortion.max_focus;
  s.flipped_triangles = flipped(d);
  s.magnification_requested = options.magnification;
  // The fold-free guard caps the lens height: a request above what this ROI, band and grid allow
  // without a fold is answered with the largest fold-free lens, and said so.
  s.magnification_limited = options.method == LensMethod::Metric && options.height <= 0 &&
                            s.magnification_center < options.magnification * (1.0 - kLimitedTolRel);
  s.iterations = d.iterations;
  s.converged = d.converged;
  s.ms_mesh = d.ms_mesh;
  s.ms_factorize = d.ms_factorize;
  s.ms_per_iteration = d.iterations > 0 ? d.ms_iterations / d.iterations : 0.0;
  s.vertices = static_cast<int>(d.positions.rows());
  s.triangles = static_cast<int>(d.triangles.rows());
}

}  // namespace

struct LensSession::Cache {
  std::deque<std::shared_ptr<const PreparedMesh>> meshes;  // most recently used first
  std::deque<CalibrationKey> calibrations;                 // most recent first
  std::unique_ptr<TranslationBase> base;                   // for LensMode::Live

  // One metric run at height h: the cached mesh and factorization if any, else a new one.
  Deformation run_metric(const std::vector<lens::RoiField>& rois, const MeshKey& key, const LensOptions& options,
                         const Progress& progress, LensSessionCounters& counters) {
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      if (!same_mesh(meshes[i]->key, key)) continue;
      std::shared_ptr<const PreparedMesh> hit = meshes[i];
      meshes.erase(meshes.begin() + static_cast<std::ptrdiff_t>(i));
      meshes.push_front(hit);
      ++counters.mesh_reuses;
      return flatten_prepared(*hit, false, options, progress);
    }
    std::shared_ptr<const PreparedMesh> made = prepare_mesh(rois, key);
    ++counters.mesh_builds;
    meshes.push_front(made);
    long long vertices = 0;
    for (const auto& m : meshes) vertices += m->texture.rows();
    while (meshes.size() > 1 && (meshes.size() > kMaxMeshes || vertices > kMaxCachedVertices)) {
      vertices -= meshes.back()->texture.rows();
      meshes.pop_back();
    }
    return flatten_prepared(*made, true, options, progress);
  }

  // The metric deformation of a request: with the height given, or calibrated (a repeated
  // request reuses its final h0); s.height and the calibration time are set.
  Deformation metric(const std::vector<lens::RoiField>& rois, const LensInput& input, const LensOptions& options,
                     const Progress& progress, LensSessionCounters& counters, LensStats& s) {
    MeshKey base;
    base.width = input.image.width, base.height = input.image.height, base.band = options.band,
    base.boundary = options.boundary;
    base.rois = input.rois;
    base.height_scale = options.height_scale;
    const auto run_at = [&](int grid, double h, const Progress& p) {
      MeshKey key = base;
      key.grid = grid;
      key.h0 = h;
      return run_metric(rois, key, options, p, counters);
    };
    CalibrationKey request;
    request.mesh = base;
    request.magnification = options.magnification, request.height = options.height, request.alpha = options.alpha;
    request.tol_rel = options.tol_rel, request.max_iterations = options.max_iterations;
    request.mesh.grid = options.grid;
    const auto known = std::find_if(calibrations.begin(), calibrations.end(),
                                    [&](const CalibrationKey& k) { return same_calibration(k, request); });
    if (known != calibrations.end()) {
      // The same request was answered before: its final h0 gives the same deformation at once.
      ++counters.calibration_reuses;
      s.height = known->h0;
      base.height_scale = known->height_scale;
      s.height_scale_per_roi = scales_per_roi(base.height_scale, rois.size());
      return run_at(options.grid, known->h0, progress);
    }
    double h0 = options.height;
    double calibration_slope = 0;  // log–log slope of the magnification in h0 (0: not calibrated)
    if (h0 <= 0) {
      const auto t_cal = Clock::now();
      const SearchResult found = coarse_height_search(run_at, rois, options);
      h0 = found.parameter;
      calibration_slope = found.slope;
      s.ms_calibration = ms_since(t_cal);
    }
    Deformation d = fold_free_run(run_at, options, h0, progress);
    if (calibration_slope > 0 && options.grid > kCalibrationGrid)
      refine_on_final_grid(run_at, rois, options, calibration_slope, progress, d, h0, s);
    if (calibration_slope > 0 && rois.size() > 1)
      equalize_lenses(run_at, rois, options, progress, d, h0, base.height_scale, s);
    s.height = h0;
    s.height_scale_per_roi = scales_per_roi(base.height_scale, rois.size());
    ++counters.calibrations;
    request.h0 = h0;
    request.height_scale = base.height_scale;
    calibrations.push_front(std::move(request));
    if (calibrations.size() > kMaxCalibrations) calibrations.pop_back();
    return d;
  }

  // The newest solved run becomes the base of later live translations (a copy of the mesh arrays).
  void keep_translation_base(const LensResult& result, const LensInput& input, const LensOptions& options) {
    auto kept = std::make_unique<TranslationBase>();
    kept->width = input.image.width, kept->height = input.image.height, kept->options = options, kept->rois = input.rois;
    kept->result.positions = result.positions;
    kept->result.texture = result.texture;
    kept->result.triangles = result.triangles;
    kept->result.stats = result.stats;
    base = std::move(kept);
  }
};

LensSession::LensSession() : cache_(std::make_unique<Cache>()) {}
LensSession::~LensSession() = default;
LensSession::LensSession(LensSession&&) noexcept = default;
LensSession& LensSession::operator=(LensSession&&) noexcept = default;

void LensSession::clear() { cache_ = std::make_unique<Cache>(); }

const LensSessionCounters& LensSession::counters() const { return counters_; }

LensResult LensSession::run(const LensInput& input, const LensOptions& options, const Progress& progress) {
  const auto t_total = Clock::now();
  validate(input, options);
  const int width = input.image.width, height = input.image.height;
  std::vector<lens::RoiField> rois;
  for (const lens::Roi& roi : input.rois) rois.push_back(lens::RoiField::build(roi, width, height, options.band));
  const bool translatable = options.method == LensMethod::Metric && options.boundary == LensBoundary::Pinned &&
                            lens_clear_of_border(input.rois, rois, width, height, options.grid, options.band);
  if (options.mode == LensMode::Live && translatable && cache_->base) {
    const TranslationBase& base = *cache_->base;
    const bool same_height = (options.height == base.options.height ||
                              (options.height > 0 && options.height == base.result.stats.height)) &&
                             (options.height_scale == base.options.height_scale ||
                              (!options.height_scale.empty() && options.height_scale == base.result.stats.height_scale_per_roi));
    const std::optional<Eigen::Vector2d> offset =
        base.width == width && base.height == height && same_height &&
                same_deformation_options(base.options, options)
            ? lens::roi_translation(base.rois, input.rois)
            : std::nullopt;
    if (offset) {
      LensResult result = translated(base, *offset, input, options, progress);
      result.stats.ms_total = ms_since(t_total);
      ++counters_.translation_reuses;
      ++counters_.runs;
      return result;
    }
  }
  progress.report("lens mesh", 0.0);

  LensResult result;
  LensStats& s = result.stats;
  Deformation d = options.method == LensMethod::Metric ? cache_->metric(rois, input, options, progress, counters_, s)
                                                       : baseline_deformation(rois, options, width, height, s);
  measure_deformation(d, rois, options, s);
  if (options.render == LensOptions::Render::On) {
    progress.report("render", 0.0);
    const auto t_render = Clock::now();
    result.image = lens::render_textured_mesh(input.image, d.positions, d.texture, d.triangles, width, height);
    s.ms_render = ms_since(t_render);
  }
  result.positions = std::move(d.positions);
  result.texture = std::move(d.texture);
  result.triangles = std::move(d.triangles);
  if (translatable && result.positions.rows() <= kMaxCachedVertices) cache_->keep_translation_base(result, input, options);
  s.ms_total = ms_since(t_total);
  progress.report("done", 1.0);
  ++counters_.runs;
  return result;
}

}  // namespace volspline::pipeline
