// SPDX-License-Identifier: MIT
#pragma once

#include <memory>

#include "core/pipeline/lens_job.h"
#include "core/common/progress.h"

namespace volspline::pipeline {

/// Counts of the work a LensSession did and skipped (for tests and the live page).
struct LensSessionCounters {
  int runs = 0;                ///< run() calls that succeeded
  int mesh_builds = 0;         ///< lens meshes built, textured and factorized (cache misses)
  int mesh_reuses = 0;         ///< flattenings that reused a cached mesh and factorization
  int calibrations = 0;        ///< h0 searches (and fold-free checks) done
  int calibration_reuses = 0;  ///< h0 searches skipped because the same request was answered before
  int translation_reuses = 0;  ///< LensMode::Live runs answered by translating the last solved run
};

/// A lens job that keeps its expensive intermediate results between runs, for live interaction.
/// Per (image size, ROIs, grid, lens height h0, band, boundary) it caches the lens mesh, its harmonic
/// texture and the factorized global-step matrix of Eq. 6.3 (lens::LensFlattener); per full metric
/// request (those keys plus magnification, height, α, tol_rel, max_iterations) it caches the final
/// h0 of the calibration. So a new α only re-runs the iterations of Algorithm 5 when the height is
/// given, and a repeated request re-runs neither the calibration nor any factorization. Results are
/// bit-identical to run_lens() with the same input and options; only the ms_* timings differ.
/// The one exception is opt-in: with LensMode::Live, a request whose ROIs only moved since the last
/// solved metric run is answered by translating that run's deformation (see LensMode::Live).
/// No key holds pixels: nothing cached depends on them (rendering always reads the input image).
/// The caches are small (a few meshes, bounded by vertex count). Not thread-safe.
class LensSession {
 public:
  /// A session with empty caches; movable, not copyable.
  LensSession();
  ~LensSession();
  LensSession(LensSession&&) noexcept;
  LensSession& operator=(LensSession&&) noexcept;
  LensSession(const LensSession&) = delete;
  LensSession& operator=(const LensSession&) = delete;

  /// Same contract as run_lens(): throws volspline::Error on bad options or ROIs, Cancelled if
  /// progress asks to stop (the caches stay valid).
  LensResult run(const LensInput& input, const LensOptions& options, const Progress& progress = {});

  /// Drops every cached mesh, factorization and calibration.
  void clear();

  /// What the session built and reused since it was made (clear() keeps the counts).
  const LensSessionCounters& counters() const;

 private:
  struct Cache;
  std::unique_ptr<Cache> cache_;
  LensSessionCounters counters_;
};

}  // namespace volspline::pipeline
