// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/volume/frame_field.h"
#include "core/volume/local_cubic_fit.h"
#include "core/volume/volume.h"

namespace volspline::volume {

/// Options of classify_materials.
struct ClassificationOptions {
  int clusters = 0;      ///< K in [2, 16], or 0 = automatic (the smallest K in [2, max_clusters] leaving <= auto_intensity_tol of the intensity variance within clusters)
  int max_clusters = 6;  ///< upper end of the automatic search, in [2, 16]
  double auto_intensity_tol = 0.1;  ///< automatic K: unexplained fraction of the intensity variance to reach, in [0, 1)
  double iso = std::numeric_limits<double>::quiet_NaN();  ///< if finite: no k-means, label 1 where the sample >= iso (sample units), else 0
  int texture_ring = 1;  ///< k of the (2k+1)^3 window of the local mean/standard-deviation features, >= 1
  int sample_limit = 20000;  ///< k-means centres are found on at most this many voxels (a fixed-stride subset), then every voxel is assigned; >= 100
  int max_iterations = 100;  ///< Lloyd iterations per K, >= 1
  double sharp_angle_deg = 30.0;  ///< a boundary voxel whose normal differs by more than this from a 26-neighbouring boundary voxel's gets no constraint, in (0, 180]
  double min_gradient_rel = 1e-3;  ///< boundary voxels whose |gradient| is below this fraction of the largest get no constraint, >= 0
  std::uint64_t seed = 1;  ///< seed of the k-means++ initialisation
};

/// Per-voxel materials (§5.2.2 iso-surface extraction) and the frame constraints they induce.
/// Labels are sorted by mean intensity: label 0 is the cluster with the lowest mean sample
/// value and is the background (dark background, as in CT/MR scans); labels >= 1 are materials.
struct MaterialClassification {
  int nx = 0;
  int ny = 0;
  int nz = 0;
  int num_clusters = 0;
  std::vector<int> label;  ///< per voxel (x fastest), in [0, num_clusters); 0 = background
  std::vector<double> cluster_mean_intensity;  ///< per label, mean sample value, ascending
  std::vector<std::size_t> cluster_size;       ///< per label, number of voxels
  /// Boundary voxels: a voxel with a 6-neighbour of a lower label (the constraint sits on the
  /// denser side of every interface), with the iso-surface normal = the fitted gradient
  /// (normalized on use). Sorted by voxel_id. Left out: voxels with a vanishing gradient, and
  /// voxels on sharp edges and corners of the iso-surface (see sharp_angle_deg), where the
  /// normal is undefined and would twist the frames; §5.3.1 corner detection finds those.
  std::vector<FrameConstraint> constraints;
  /// Automatic K: within-cluster sum of squares of the normalized features for K = 1, 2, ...
  /// (index K - 1) up to the chosen K; empty when K was given or iso was used.
  std::vector<double> within_sum_squares;
  /// Automatic K: fraction of the intensity variance left within the clusters, same indexing.
  std::vector<double> intensity_unexplained;
  std::size_t num_foreground = 0;  ///< voxels with label >= 1
};

/// Classifies the voxels into materials (§5.2.2): k-means on per-voxel features, each
/// normalized to zero mean and unit variance and then weighted (intensity 1, local mean 1,
/// gradient magnitude 0.5, local standard deviation 0.5, Hessian Frobenius norm 0.25, so
/// intensity-like features dominate and thin edge layers do not become clusters of their own);
/// or, with options.iso, a threshold. `fit` is fit_local_cubics(volume).
/// Deviation: the thesis lists 16 Haralick texture statistics; we keep the intensity,
/// derivative and local mean/variance ones, which separate the materials of our test volumes.
/// Throws volspline::Error on bad options or if fit does not match the volume's grid.
MaterialClassification classify_materials(const Volume& volume, const LocalCubicFit& fit,
                                          const ClassificationOptions& options = {});

/// 1 for every voxel within `margin` voxels (Chebyshev distance) of a foreground voxel (label
/// >= 1), else 0: the active set of smooth_frame_field. margin >= 0.
std::vector<std::uint8_t> foreground_mask(const MaterialClassification& classes, int margin);

}  // namespace volspline::volume
