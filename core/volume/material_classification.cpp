// SPDX-License-Identifier: MIT
#include "core/volume/material_classification.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

#include "core/common/error.h"
#include "core/volume/kmeans.h"

namespace volspline::volume {

namespace {

constexpr int kNumFeatures = 5;
// Intensity, local mean, gradient magnitude, local standard deviation, Hessian norm: the
// intensity-like features dominate so that the thin layer of high-gradient voxels along an
// interface joins one of the two materials instead of forming a cluster of its own.
constexpr double kFeatureWeights[kNumFeatures] = {1.0, 1.0, 0.5, 0.5, 0.25};

// Box sums of `values` over the (2r+1)^3 window clamped to the grid, separably along x, y, z.
std::vector<double> box_mean(const std::vector<double>& values, int nx, int ny, int nz, int r) {
  std::vector<double> a = values;
  std::vector<double> b(values.size());
  const int dims[3] = {nx, ny, nz};
  const std::size_t strides[3] = {1, static_cast<std::size_t>(nx), static_cast<std::size_t>(nx) * ny};
  std::vector<double> count(values.size(), 1.0);
  std::vector<double> count_next(values.size());
  for (int axis = 0; axis < 3; ++axis) {
    const int len = dims[axis];
    const std::size_t stride = strides[axis];
    for (std::size_t base = 0; base < values.size(); ++base) {
      // `base` is the first voxel of a line along `axis` when its coordinate on that axis is 0.
      if ((base / stride) % len != 0) continue;
      std::vector<double> prefix(len + 1, 0.0);
      std::vector<double> prefix_count(len + 1, 0.0);
      for (int t = 0; t < len; ++t) {
        prefix[t + 1] = prefix[t] + a[base + t * stride];
        prefix_count[t + 1] = prefix_count[t] + count[base + t * stride];
      }
      for (int t = 0; t < len; ++t) {
        const int lo = std::max(0, t - r);
        const int hi = std::min(len - 1, t + r);
        b[base + t * stride] = prefix[hi + 1] - prefix[lo];
        count_next[base + t * stride] = prefix_count[hi + 1] - prefix_count[lo];
      }
    }
    std::swap(a, b);
    std::swap(count, count_next);
  }
  for (std::size_t i = 0; i < a.size(); ++i) a[i] /= count[i];
  return a;
}

void check_options(const ClassificationOptions& o) {
  if (o.clusters != 0 && (o.clusters < 2 || o.clusters > 16))
    throw Error("classification: clusters must be 0 (automatic) or in [2, 16], got " + std::to_string(o.clusters));
  if (o.max_clusters < 2 || o.max_clusters > 16)
    throw Error("classification: max_clusters must be in [2, 16], got " + std::to_string(o.max_clusters));
  if (o.texture_ring < 1) throw Error("classification: texture_ring must be >= 1, got " + std::to_string(o.texture_ring));
  if (o.sample_limit < 100) throw Error("classification: sample_limit must be >= 100, got " + std::to_string(o.sample_limit));
  if (o.max_iterations < 1) throw Error("classification: max_iterations must be >= 1, got " + std::to_string(o.max_iterations));
  if (!(o.auto_intensity_tol >= 0 && o.auto_intensity_tol < 1)) throw Error("classification: auto_intensity_tol must be in [0, 1)");
  if (!(o.sharp_angle_deg > 0 && o.sharp_angle_deg <= 180)) throw Error("classification: sharp_angle_deg must be in (0, 180]");
  if (!(o.min_gradient_rel >= 0)) throw Error("classification: min_gradient_rel must be >= 0");
  if (std::isinf(o.iso)) throw Error("classification: iso must be finite");
}

// Within-cluster sum of squares of feature column 0 (intensity) of `points` under `assignment`.
double intensity_within(const Eigen::MatrixXd& points, const std::vector<int>& assignment, int k) {
  std::vector<double> sum(k, 0.0), sum_sq(k, 0.0);
  std::vector<double> count(k, 0.0);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const double v = points(i, 0);
    sum[assignment[i]] += v;
    sum_sq[assignment[i]] += v * v;
    count[assignment[i]] += 1;
  }
  double total = 0.0;
  for (int c = 0; c < k; ++c)
    if (count[c] > 0) total += std::max(0.0, sum_sq[c] - sum[c] * sum[c] / count[c]);
  return total;
}

// §5.2.2: per-voxel statistics (intensity, box mean, gradient norm, box deviation, Hessian norm),
// normalized to zero mean and unit variance, then weighted; a feature that is only round-off of
// the fit (deviation ≤ 1e-9 of the sample range) is zero.
Eigen::MatrixXd texture_features(const Volume& volume, const LocalCubicFit& fit, const ClassificationOptions& options,
                                 double range) {
  const std::size_t n = volume.num_voxels();
  std::vector<double> intensity(volume.samples.begin(), volume.samples.end());
  std::vector<double> squares(n);
  for (std::size_t i = 0; i < n; ++i) squares[i] = intensity[i] * intensity[i];
  const std::vector<double> mean = box_mean(intensity, volume.nx, volume.ny, volume.nz, options.texture_ring);
  const std::vector<double> mean_sq = box_mean(squares, volume.nx, volume.ny, volume.nz, options.texture_ring);
  Eigen::MatrixXd features(static_cast<Eigen::Index>(n), kNumFeatures);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Index r = static_cast<Eigen::Index>(i);
    features(r, 0) = intensity[i];
    features(r, 1) = mean[i];
    features(r, 2) = fit.gradient[i].norm();
    features(r, 3) = std::sqrt(std::max(0.0, mean_sq[i] - mean[i] * mean[i]));
    features(r, 4) = fit.hessian[i].norm();
  }
  for (int f = 0; f < kNumFeatures; ++f) {
    const double mu = features.col(f).mean();
    const double sigma = std::sqrt((features.col(f).array() - mu).square().mean());
    if (sigma > 1e-9 * range)  // below: round-off of the fit, not a feature
      features.col(f) = (features.col(f).array() - mu) * (kFeatureWeights[f] / sigma);
    else
      features.col(f).setZero();
  }
  return features;
}

// k-means on the subset, K given or automatic (result.within_sum_squares and
// intensity_unexplained record the automatic search).
KMeansResult choose_clusters(const Eigen::MatrixXd& subset, const ClassificationOptions& options,
                             MaterialClassification& result) {
  const Eigen::Index m = subset.rows();
  KMeansOptions km;
  km.max_iterations = options.max_iterations;
  km.seed = options.seed;
  KMeansResult chosen;
  if (options.clusters > 0) {
    km.clusters = static_cast<int>(std::min<Eigen::Index>(options.clusters, m));
    return kmeans(subset, km);
  }
  // Automatic K: the materials are intensity levels; the other features help place the voxels
  // but would always reward more clusters (the blurred layer along an interface), so K is the
  // smallest one whose clusters explain all but auto_intensity_tol of the intensity variance.
  const Eigen::RowVectorXd centroid = subset.colwise().mean();
  result.within_sum_squares.push_back((subset.rowwise() - centroid).rowwise().squaredNorm().sum());
  const double intensity_total = (subset.col(0).array() - centroid[0]).square().sum();
  result.intensity_unexplained.push_back(1.0);
  for (int k = 2; k <= options.max_clusters && k <= m; ++k) {
    km.clusters = k;
    chosen = kmeans(subset, km);
    result.within_sum_squares.push_back(chosen.within_sum_squares);
    const double fraction = intensity_total > 0 ? intensity_within(subset, chosen.assignment, k) / intensity_total : 0.0;
    result.intensity_unexplained.push_back(fraction);
    if (fraction <= options.auto_intensity_tol) break;
  }
  return chosen;
}

// Every voxel to its nearest centre, then labels by ascending mean intensity (ties: k-means
// index); empty clusters are dropped. Sets result.label and num_clusters.
void assign_labels(const Volume& volume, const Eigen::MatrixXd& features, const KMeansResult& chosen,
                   MaterialClassification& result) {
  const std::size_t n = volume.num_voxels();
  const int k = static_cast<int>(chosen.centers.rows());
  std::vector<int> raw(n);
  for (std::size_t i = 0; i < n; ++i) {
    int best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (int c = 0; c < k; ++c) {
      const double d = (features.row(static_cast<Eigen::Index>(i)) - chosen.centers.row(c)).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = c;
      }
    }
    raw[i] = best;
  }
  std::vector<double> sum(k, 0.0);
  std::vector<std::size_t> count(k, 0);
  for (std::size_t i = 0; i < n; ++i) {
    sum[raw[i]] += volume.samples[i];
    ++count[raw[i]];
  }
  std::vector<int> order;
  for (int c = 0; c < k; ++c)
    if (count[c] > 0) order.push_back(c);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return sum[a] / count[a] < sum[b] / count[b]; });
  std::vector<int> relabel(k, 0);
  for (std::size_t r = 0; r < order.size(); ++r) relabel[order[r]] = static_cast<int>(r);
  for (std::size_t i = 0; i < n; ++i) result.label[i] = relabel[raw[i]];
  result.num_clusters = std::max<int>(2, static_cast<int>(order.size()));
}

// Mean intensity and size per cluster, and the foreground count.
void cluster_statistics(const Volume& volume, MaterialClassification& result) {
  result.cluster_mean_intensity.assign(result.num_clusters, 0.0);
  result.cluster_size.assign(result.num_clusters, 0);
  for (std::size_t i = 0; i < volume.num_voxels(); ++i) {
    result.cluster_mean_intensity[result.label[i]] += volume.samples[i];
    ++result.cluster_size[result.label[i]];
  }
  for (int c = 0; c < result.num_clusters; ++c) {
    if (result.cluster_size[c] > 0) result.cluster_mean_intensity[c] /= static_cast<double>(result.cluster_size[c]);
    if (c > 0) result.num_foreground += result.cluster_size[c];
  }
}

// Iso-surface constraints (§5.2.2) on the higher-label side of every interface, where the
// gradient is at least min_gradient_rel of the largest.
std::vector<FrameConstraint> interface_constraints(const Volume& volume, const LocalCubicFit& fit,
                                                   const ClassificationOptions& options,
                                                   const std::vector<int>& labels) {
  const std::size_t n = volume.num_voxels();
  double max_gradient = 0.0;
  for (std::size_t i = 0; i < n; ++i) max_gradient = std::max(max_gradient, fit.gradient[i].norm());
  const double min_gradient = std::max(options.min_gradient_rel * max_gradient, std::numeric_limits<double>::min());
  const std::size_t sy = volume.nx;
  const std::size_t sz = static_cast<std::size_t>(volume.nx) * volume.ny;
  std::vector<FrameConstraint> constraints;
  for (int z = 0; z < volume.nz; ++z)
    for (int y = 0; y < volume.ny; ++y)
      for (int x = 0; x < volume.nx; ++x) {
        const std::size_t id = volume.index(x, y, z);
        const int label = labels[id];
        if (label == 0) continue;
        const bool boundary = (x > 0 && labels[id - 1] < label) || (x + 1 < volume.nx && labels[id + 1] < label) ||
                              (y > 0 && labels[id - sy] < label) || (y + 1 < volume.ny && labels[id + sy] < label) ||
                              (z > 0 && labels[id - sz] < label) || (z + 1 < volume.nz && labels[id + sz] < label);
        if (!boundary || !(fit.gradient[id].norm() >= min_gradient)) continue;
        constraints.push_back({id, fit.gradient[id].normalized()});
      }
  return constraints;
}

// Sharp features: drops a constraint whose normal differs by more than sharp_angle_deg from a
// 26-neighbouring constraint's (decided on the original set, so the result is order-free).
std::vector<FrameConstraint> without_sharp_features(const Volume& volume, const std::vector<FrameConstraint>& constraints,
                                                    double sharp_angle_deg) {
  const std::size_t sz = static_cast<std::size_t>(volume.nx) * volume.ny;
  std::vector<int> constraint_of(volume.num_voxels(), -1);
  for (std::size_t c = 0; c < constraints.size(); ++c) constraint_of[constraints[c].voxel_id] = static_cast<int>(c);
  const double cos_sharp = std::cos(sharp_angle_deg * (3.14159265358979323846 / 180.0));
  std::vector<FrameConstraint> kept;
  for (const FrameConstraint& fc : constraints) {
    const int x = static_cast<int>(fc.voxel_id % volume.nx);
    const int y = static_cast<int>((fc.voxel_id / volume.nx) % volume.ny);
    const int z = static_cast<int>(fc.voxel_id / sz);
    bool sharp = false;
    for (int zz = std::max(0, z - 1); zz <= std::min(volume.nz - 1, z + 1) && !sharp; ++zz)
      for (int yy = std::max(0, y - 1); yy <= std::min(volume.ny - 1, y + 1) && !sharp; ++yy)
        for (int xx = std::max(0, x - 1); xx <= std::min(volume.nx - 1, x + 1) && !sharp; ++xx) {
          const int other = constraint_of[volume.index(xx, yy, zz)];
          sharp = other >= 0 && fc.normal.dot(constraints[other].normal) < cos_sharp;
        }
    if (!sharp) kept.push_back(fc);
  }
  return kept;
}

}  // namespace

MaterialClassification classify_materials(const Volume& volume, const LocalCubicFit& fit, const ClassificationOptions& options) {
  check_options(options);
  const std::size_t n = volume.num_voxels();
  if (fit.nx != volume.nx || fit.ny != volume.ny || fit.nz != volume.nz || fit.value.size() != n ||
      fit.gradient.size() != n || fit.hessian.size() != n)
    throw Error("classification: the local cubic fit does not match the volume's " + std::to_string(volume.nx) + "x" +
                std::to_string(volume.ny) + "x" + std::to_string(volume.nz) + " grid");
  if (n == 0) throw Error("classification: empty volume");

  MaterialClassification result;
  result.nx = volume.nx;
  result.ny = volume.ny;
  result.nz = volume.nz;
  result.label.assign(n, 0);

  const auto [min_sample, max_sample] = std::minmax_element(volume.samples.begin(), volume.samples.end());
  const double range = static_cast<double>(*max_sample) - static_cast<double>(*min_sample);
  if (std::isfinite(options.iso) || range == 0.0) {
    // A threshold; a constant volume is all background (its fitted derivatives are round-off).
    result.num_clusters = 2;
    if (std::isfinite(options.iso))
      for (std::size_t i = 0; i < n; ++i) result.label[i] = volume.samples[i] >= options.iso ? 1 : 0;
  } else {
    const Eigen::MatrixXd features = texture_features(volume, fit, options, range);
    // Centres from a fixed-stride subset (deterministic), then every voxel is assigned.
    const std::size_t stride = (n + options.sample_limit - 1) / options.sample_limit;
    const Eigen::Index m = static_cast<Eigen::Index>((n + stride - 1) / stride);
    Eigen::MatrixXd subset(m, kNumFeatures);
    for (Eigen::Index s = 0; s < m; ++s) subset.row(s) = features.row(static_cast<Eigen::Index>(s * stride));
    assign_labels(volume, features, choose_clusters(subset, options, result), result);
  }
  cluster_statistics(volume, result);
  result.constraints =
      without_sharp_features(volume, interface_constraints(volume, fit, options, result.label), options.sharp_angle_deg);
  return result;
}

std::vector<std::uint8_t> foreground_mask(const MaterialClassification& classes, int margin) {
  assert(margin >= 0);
  const int nx = classes.nx, ny = classes.ny, nz = classes.nz;
  const std::size_t n = classes.label.size();
  std::vector<std::uint8_t> mask(n, 0);
  for (std::size_t i = 0; i < n; ++i) mask[i] = classes.label[i] > 0;
  // Chebyshev dilation, separably along x, y, z.
  const int dims[3] = {nx, ny, nz};
  const std::size_t strides[3] = {1, static_cast<std::size_t>(nx), static_cast<std::size_t>(nx) * ny};
  std::vector<std::uint8_t> next(n);
  for (int axis = 0; axis < 3 && margin > 0; ++axis) {
    for (std::size_t i = 0; i < n; ++i) {
      const int t = static_cast<int>((i / strides[axis]) % dims[axis]);
      std::uint8_t on = 0;
      for (int d = -margin; d <= margin && !on; ++d) {
        const int s = t + d;
        if (s >= 0 && s < dims[axis]) on = mask[i + static_cast<std::ptrdiff_t>(d) * static_cast<std::ptrdiff_t>(strides[axis])];
      }
      next[i] = on;
    }
    std::swap(mask, next);
  }
  return mask;
}

}  // namespace volspline::volume
