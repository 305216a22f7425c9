// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/common/image.h"
#include "core/lens/roi.h"
#include "core/mesh/triangle_mesh.h"
#include "core/common/progress.h"

namespace volspline::pipeline {

/// How the lens deforms the image.
enum class LensMethod {
  Metric,   ///< thesis ch. 6: lens mesh, harmonic texture, metric flattening (Algorithm 5)
  Fisheye,  ///< Sarkar–Brown graphical fisheye (baseline)
  Bifocal,  ///< piecewise linear radial bifocal lens (baseline)
  Zoom,     ///< magnified inset (baseline)
};

/// What stays fixed while the metric lens is flattened.
enum class LensBoundary {
  Pinned,  ///< the image border and everything beyond each ROI's context band keep their place
  Square,  ///< §6.4 boundary control: only the image border, on a square scaled by √(A_lens/A_image); the result is scaled back to the image size
};

/// How exactly a request is answered (metric lens in a LensSession; run_lens() always solves).
enum class LensMode {
  Full,  ///< always the full job: results depend only on the input and the other options
  Live,  ///< interactive preview while the user drags: a LensSession may answer a request whose ROIs
         ///< are a pure translation of its last solved metric run (same shapes, sizes and options,
         ///< pinned boundary, the lens and its context band clear of the image border in both places)
         ///< with that run's deformation moved by the offset, without solving again (stats.translated);
         ///< it differs from a full run only by where the grid samples the lens. Otherwise as Full.
};

/// Options of the lens job; every field is checked on entry.
struct LensOptions {
  LensMethod method = LensMethod::Metric;
  double magnification = 2.0;  ///< wanted linear magnification at each ROI centre, in (1, 16]
  double height = 0.0;         ///< > 0: lens height h0 in ROI inscribed radii (metric only, skips the calibration); ≤ 50
  /// Metric with height > 0: each ROI's height relative to h0 (one entry per ROI, each in (0, 10]),
  /// as stats.height_scale_per_roi reports it; empty: 1 each. A calibrated run with several ROIs
  /// chooses them itself.
  std::vector<double> height_scale;
  double alpha = 0.0;          ///< Eq. 6.8 blend in [0, 1]: 0 rigid, 1 conformal
  int grid = 100;              ///< grid vertices along the longer image side, in [4, 2000]
  LensBoundary boundary = LensBoundary::Pinned;
  double band = 0.75;          ///< free context band around each ROI, in ROI equivalent radii, in (0, 10]
  double tol_rel = 1e-3;       ///< flattening stops when the energy changes by less than this fraction
  int max_iterations = 300;    ///< flattening iterations at most, in [1, 100000]
  enum class Render { Off, On } render = Render::On;  ///< render the output image (Off: mesh and stats only)
  LensMode mode = LensMode::Full;
};

/// Input of the lens job.
struct LensInput {
  Image image;             ///< the picture, 8-bit, 1–4 channels
  std::vector<lens::Roi> rois;   ///< at least one
  std::string name = "image";    ///< used in error messages
};

/// Numbers reported by the lens job (the stats JSON keys).
struct LensStats {
  double distortion_sum = 0;       ///< Eq. 6.9 over all grid triangles, the whole image (lens_measures.h)
  double distortion_max = 0;
  double distortion_sum_focus = 0; ///< Eq. 6.9 over the focus: grid triangles whose texture centroid is inside a ROI
  double distortion_max_focus = 0;
  double magnification_center = 0; ///< measured, mean over the ROIs
  std::vector<double> magnification_per_roi;
  double magnification_requested = 0;  ///< options.magnification
  /// The metric lens stopped below the request (by more than 3 %): its fold-free guard allows at
  /// most magnification_center here (a wider band does not raise it: the fold-free height does).
  bool magnification_limited = false;
  int flipped_triangles = 0;       ///< exported triangles turned over against the texture (count_flipped_triangles)
  int iterations = 0;              ///< flattening iterations of the final run (0 for baselines)
  bool converged = true;
  bool translated = false;         ///< LensMode::Live answered by moving an earlier run's deformation (its stats)
  double height = 0;               ///< lens height h0 used, in ROI inscribed radii (metric)
  std::vector<double> height_scale_per_roi;  ///< each ROI's height relative to h0 (metric; 1 each for one ROI)
  double baseline_parameter = 0;   ///< the baselines' magnification parameter after calibration
  int vertices = 0;                ///< output mesh vertices
  int triangles = 0;               ///< output mesh triangles
  double ms_total = 0;             ///< whole job, calibration and rendering included
  double ms_calibration = 0;       ///< search of h0 (coarse-grid secant, plus at most one final-grid correction run)
  double ms_mesh = 0;              ///< lens mesh and texture of the final run
  double ms_factorize = 0;         ///< one sparse factorization of the final run
  double ms_per_iteration = 0;     ///< mean local+global iteration of the final run
  double ms_render = 0;
};

/// Result of the lens job: the flattened textured mesh, the rendered image and the stats.
struct LensResult {
  Image image;            ///< same size and channels as the input (empty if !render)
  Eigen::MatrixX2d positions;   ///< n×2 output pixel positions
  Eigen::MatrixX2d texture;     ///< n×2 input pixel positions (texture coordinates)
  mesh::Triangles triangles;    ///< m×3
  LensStats stats;
};

/// Runs the focus+context lens of thesis ch. 6 (or a baseline) on an image.
/// Throws volspline::Error on bad options (message names the option) or bad ROIs (names the ROI),
/// Cancelled if progress asks to stop.
LensResult run_lens(const LensInput& input, const LensOptions& options, const Progress& progress = {});

}  // namespace volspline::pipeline
