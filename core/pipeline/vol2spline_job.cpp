// SPDX-License-Identifier: MIT
#include "core/pipeline/vol2spline_job.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/LU>

#include "core/common/error.h"
#include "core/io/number_text.h"
#include "core/mesh/hex_quality.h"
#include "core/pipeline/stage_timer.h"
#include "core/spline/scattered_density_fitting.h"
#include "core/volume/corner_detection.h"
#include "core/volume/field_aligned_param.h"
#include "core/volume/hessian_frames.h"
#include "core/volume/local_cubic_fit.h"
#include "core/volume/material_classification.h"

namespace volspline::pipeline {

namespace {

constexpr double kPi = 3.14159265358979323846;

void check_options(const Vol2SplineOptions& o) {
  if (!(o.max_rms_rel > 0.0) || !std::isfinite(o.max_rms_rel)) throw Error("vol2spline: max_rms_rel must be > 0");
  if (o.max_control_points != 0 && o.max_control_points < 64)
    throw Error("vol2spline: max_control_points must be 0 (automatic) or >= 64");
  if (!(o.min_gain_rate >= 0.0) || !std::isfinite(o.min_gain_rate)) throw Error("vol2spline: min_gain_rate must be >= 0");
  if (o.max_levels < 0 || o.max_levels > 20) throw Error("vol2spline: max_levels must be in [0, 20]");
  if (o.initial_cells < 0 || o.initial_cells > 256) throw Error("vol2spline: initial_cells must be in [0, 256]");
  if (o.clusters != 0 && (o.clusters < 2 || o.clusters > 16)) throw Error("vol2spline: clusters must be 0 or in [2, 16]");
  if (o.threads < 1 || o.threads > 256) throw Error("vol2spline: threads must be in [1, 256]");
}

// The volume the stages work on, and the length `scale` that maps it back: world = origin +
// direction · (scale · p). Its spacing is divided by the largest component (largest 1) and its
// origin and direction are dropped, so a volume and its copy in other units or at another place
// give the stages the same numbers: the classification's features, the Hessian frames and the
// parameterization's operators scale with the spacing, and their thresholds do not.
struct UnitVolume {
  volume::Volume volume;
  double scale = 1.0;
};

UnitVolume unit_volume_of(const volume::Volume& volume, const std::string& name) {
  const Eigen::Vector3d& s = volume.spacing;
  const auto values = [](const Eigen::Vector3d& v) {
    std::string text = "(";
    for (int a = 0; a < 3; ++a) {
      io::append_number(text, v(a));
      text += a < 2 ? ", " : ")";
    }
    return text;
  };
  if (!s.allFinite() || !(s.minCoeff() > 0.0))
    throw Error("vol2spline: volume '" + name + "' has spacing " + values(s) + "; every voxel size must be a positive number");
  if (s.minCoeff() < 1e-12 * s.maxCoeff())
    throw Error("vol2spline: volume '" + name + "' has spacing " + values(s) +
                ": voxel sizes more than 1e12 apart cannot be fitted together");
  if (!volume.origin.allFinite() || !volume.direction.allFinite())
    throw Error("vol2spline: volume '" + name + "' has an origin or direction that is not finite");
  UnitVolume unit{volume, s.maxCoeff()};
  unit.volume.spacing = s / unit.scale;
  unit.volume.origin.setZero();
  unit.volume.direction.setIdentity();
  return unit;
}

// Smallest scaled Jacobian det J / (|J_u| |J_v| |J_w|) of the geometry (X, Y, Z) at the cell
// centres of a 16³ lattice of the domain.
double spline_min_scaled_jacobian(const spline::TSpline& s) {
  constexpr int kCells = 16;
  const Eigen::Vector3d lo = s.domain_min(), hi = s.domain_max();
  double worst = 1.0;
  const int d = s.dimension();
  std::vector<double> value(d), jac(3 * d);
  for (int k = 0; k < kCells; ++k)
    for (int j = 0; j < kCells; ++j)
      for (int i = 0; i < kCells; ++i) {
        const Eigen::Vector3d t((i + 0.5) / kCells, (j + 0.5) / kCells, (k + 0.5) / kCells);
        const Eigen::Vector3d uvw = lo + (hi - lo).cwiseProduct(t);
        s.evaluate_with_jacobian(uvw, spline::TSplineForm::SemiStandard, value.data(), jac.data());
        Eigen::Matrix3d m;
        for (int a = 0; a < 3; ++a)
          for (int r = 0; r < 3; ++r) m(r, a) = jac[r + d * a];
        worst = std::min(worst, mesh::scaled_jacobian(m));
      }
  return worst;
}

// The frame stages (§5.2): local cubic fits, Hessian frames, classification, frame smoothing,
// and with Vol2SplineParam::Aligned the field-aligned parameterization (§5.3).
struct FrameStages {
  volume::FrameField smoothed;
  Eigen::MatrixX3d uvw;  // per voxel; empty unless aligned
};

FrameStages run_frame_stages(const volume::Volume& volume, const std::string& name, const Vol2SplineOptions& options,
                             bool aligned, const Progress& progress, StageTimer& timer, Vol2SplineStats& stats) {
  if (volume.nx < 5 || volume.ny < 5 || volume.nz < 5)
    throw Error("vol2spline: volume '" + name + "' needs at least 5 voxels along every axis for the frame field");
  FrameStages out;
  progress.report("local cubic fit", 0.0);
  volume::LocalCubicFitOptions cubic;
  cubic.threads = options.threads;
  const volume::LocalCubicFit fit = volume::fit_local_cubics(volume, cubic, progress);
  timer.end_stage("local_cubic_fit");
  progress.report("hessian frames", 0.0);
  volume::FrameField initial{volume.nx, volume.ny, volume.nz, volume::hessian_frames(fit.hessian, options.threads)};
  timer.end_stage("hessian_frames");
  progress.report("classification", 0.0);
  volume::ClassificationOptions classification;
  classification.clusters = options.clusters;
  classification.iso = options.iso;
  const volume::MaterialClassification classes = volume::classify_materials(volume, fit, classification);
  stats.clusters = classes.num_clusters;
  stats.constraints = static_cast<int>(classes.constraints.size());
  timer.end_stage("classification");
  volume::FrameSmoothingOptions smoothing;
  smoothing.active = volume::foreground_mask(classes, 2);
  smoothing.threads = options.threads;
  const volume::FrameSmoothingResult smooth = volume::smooth_frame_field(initial, classes.constraints, smoothing, progress);
  stats.frames_computed = true;
  stats.frame_smoothness_initial = smooth.initial_energy;
  stats.frame_smoothness_final = smooth.final_energy;
  stats.frame_iterations = smooth.iterations;
  stats.constraint_angle_max_deg = smooth.max_constraint_angle_rad * 180.0 / kPi;
  out.smoothed = smooth.field;
  timer.end_stage("frame_smoothing");
  if (!aligned) return out;
  progress.report("parameterization", 0.0);
  volume::FieldAlignedOptions param;
  param.threads = options.threads;
  if (!options.corners.empty()) {
    for (std::size_t id : options.corners)
      if (id >= volume.num_voxels())
        throw Error("vol2spline: corner voxel " + std::to_string(id) + " is outside volume '" + name + "'");
    param.corner_selection = volume::CornerSelection::Given;
    param.corner_voxels = options.corners;
  }
  const volume::FieldAlignedParam map = volume::compute_field_aligned_param(volume, out.smoothed, classes, param, progress);
  stats.corners = static_cast<int>(map.corner_voxels.size());
  stats.param_min_jacobian = map.min_jacobian;
  stats.param_inverted_cells = map.inverted_cells;
  out.uvw = map.uvw;
  timer.end_stage("parameterization");
  return out;
}

// What the stats need of the adaptive fit besides the spline.
struct DensityFit {
  std::vector<double> reconstruction;
  std::vector<spline::AdaptiveDensityLevel> curve;
  spline::GridError error;
  spline::FitStopReason stop = spline::FitStopReason::Target;
};

// Identity: the density over the voxel indices (X, Y, Z = index × spacing); aligned: Eq. 5.11,
// (X, Y, Z, density) over the aligned parameters uvw.
spline::TSpline fit_density(const volume::Volume& volume, const spline::GridSamples& samples,
                            const spline::AdaptiveDensityOptions& fit, const Eigen::MatrixX3d* uvw,
                            const Progress& progress, DensityFit& out) {
  if (!uvw) {
    spline::AdaptiveDensityResult r = spline::fit_density_adaptive(samples, fit, progress);
    out.reconstruction = std::move(r.reconstruction);
    out.curve = std::move(r.levels);
    out.error = r.error;
    out.stop = r.stop_reason;
    Eigen::MatrixXd points = r.spline.points();
    for (int a = 0; a < 3; ++a) points.col(a) *= volume.spacing(a);
    r.spline.set_points(std::move(points));
    return std::move(r.spline);
  }
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(volume.num_voxels()), 4);
  for (int z = 0; z < volume.nz; ++z)
    for (int y = 0; y < volume.ny; ++y)
      for (int x = 0; x < volume.nx; ++x) {
        const auto v = static_cast<Eigen::Index>(volume.index(x, y, z));
        targets(v, 0) = x * volume.spacing.x();
        targets(v, 1) = y * volume.spacing.y();
        targets(v, 2) = z * volume.spacing.z();
        targets(v, 3) = volume.samples[static_cast<std::size_t>(v)];
      }
  spline::ScatteredDensityResult r = spline::fit_scattered_adaptive(*uvw, targets, samples.dims, fit, progress);
  out.reconstruction = std::move(r.reconstruction);
  out.curve = std::move(r.levels);
  out.stop = r.stop_reason;
  out.error = spline::grid_error(samples, out.reconstruction);
  return std::move(r.spline);
}

}  // namespace

Vol2SplineResult run_vol2spline(const volume::Volume& input, const std::string& name,
                                const Vol2SplineOptions& options, const Progress& progress) {
  check_options(options);
  if (input.nx < 2 || input.ny < 2 || input.nz < 2)
    throw Error("vol2spline: volume '" + name + "' needs at least 2 voxels along every axis");
  if (input.samples.size() != input.num_voxels())
    throw Error("vol2spline: volume '" + name + "' has " + std::to_string(input.samples.size()) +
                " samples for " + std::to_string(input.num_voxels()) + " voxels");
  const UnitVolume unit = unit_volume_of(input, name);
  const volume::Volume& volume = unit.volume;
  Vol2SplineStats stats;
  stats.voxels = volume.num_voxels();
  StageTimer timer(stats.times_s);
  const bool aligned = options.param == Vol2SplineParam::Aligned;
  const bool frames = aligned || options.compute_frames == Vol2SplineOptions::ComputeFrames::On;
  FrameStages stages;
  if (frames) stages = run_frame_stages(volume, name, options, aligned, progress, timer, stats);

  progress.report("fit", 0.0);
  spline::GridSamples samples;
  samples.dims = {volume.nx, volume.ny, volume.nz};
  samples.values.assign(volume.samples.begin(), volume.samples.end());
  spline::AdaptiveDensityOptions fit;
  fit.max_rms_rel = options.max_rms_rel;
  fit.max_control_points = options.max_control_points > 0 ? options.max_control_points
                                                          : spline::automatic_control_point_budget(volume.num_voxels());
  stats.max_control_points = fit.max_control_points;
  fit.max_levels = options.max_levels;
  fit.min_gain_rate = options.min_gain_rate;
  fit.initial_cells = options.initial_cells;
  fit.fit.threads = options.threads;
  DensityFit density;
  spline::TSpline result_spline = fit_density(volume, samples, fit, aligned ? &stages.uvw : nullptr, progress, density);
  timer.end_stage("fit");
  stats.density_rms_rel = density.error.rms_rel;
  stats.density_max_rel = density.error.max_rel;
  stats.control_points = result_spline.num_functions();
  stats.levels = static_cast<int>(density.curve.size()) - 1;
  stats.stop_reason = spline::fit_stop_reason_name(density.stop);
  stats.curve = density.curve;
  stats.min_scaled_jacobian = spline_min_scaled_jacobian(result_spline);
  // Eq. 5.11's X, Y, Z in the file's units and world: an affine map of the control points is the
  // same map of the spline (its basis sums to 1). Applied after the measures: a mirrored frame
  // (det < 0, as LPS files have) would flip the Jacobian's sign without folding anything.
  if (unit.scale != 1.0 || !input.world_is_grid()) {
    Eigen::MatrixXd points = result_spline.points();
    for (Eigen::Index i = 0; i < points.rows(); ++i)
      points.row(i).head<3>() = input.world_from_grid(unit.scale * points.row(i).head<3>().transpose()).transpose();
    result_spline.set_points(std::move(points));
  }
  timer.end_stage("measures");
  progress.report("fit", 1.0);
  return {std::move(result_spline), std::move(stats), std::move(density.reconstruction), std::move(stages.smoothed),
          std::move(stages.uvw)};
}

}  // namespace volspline::pipeline
