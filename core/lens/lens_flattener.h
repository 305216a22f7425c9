// SPDX-License-Identifier: MIT
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/lens/flatten.h"
#include "core/mesh/triangle_mesh.h"
#include "core/common/progress.h"

namespace volspline::lens {

/// A reusable flattening session for one lens mesh (§6.4, Algorithm 5). compute() does the part
/// that depends only on the mesh: the standard triangles T^d, the weights (1+h)·A·cotθ and the
/// factorization of the global-step matrix W of Eq. 6.3. flatten() then runs only the local/global
/// iterations, so a new metric blend α or a new start reuses the factorization. flatten_lens() is
/// compute() followed by one flatten(); both give bit-identical positions.
class LensFlattener {
 public:
  /// An empty session (ready() is false until compute()); movable, not copyable.
  LensFlattener();
  ~LensFlattener();
  LensFlattener(LensFlattener&&) noexcept;
  LensFlattener& operator=(LensFlattener&&) noexcept;
  LensFlattener(const LensFlattener&) = delete;
  LensFlattener& operator=(const LensFlattener&) = delete;

  /// Builds and factorizes W for the mesh: xyz n×3 (pixels), triangles m×3, pinned n flags;
  /// h in the weights is z / height_unit. Preconditions as flatten_lens(). Replaces any earlier
  /// mesh. Throws volspline::Error if the factorization fails (the session is then empty).
  void compute(const mesh::Positions& xyz, const mesh::Triangles& triangles, const std::vector<char>& pinned,
               double height_unit);

  /// Runs the iterations of Algorithm 5 from `start` (n×2 pixels; pinned vertices stay at their
  /// row) with the metric blend, tolerance and iteration limit of `options` (its height_unit is
  /// ignored: it was fixed by compute()). ms_setup and ms_factorize of the result are those of
  /// compute(). Throws volspline::Error if compute() has not succeeded or start has the wrong
  /// shape, Cancelled if progress asks to stop.
  FlattenResult flatten(const Eigen::MatrixX2d& start, const FlattenOptions& options,
                        const Progress& progress = {}) const;

  /// True once compute() has succeeded.
  bool ready() const;
  /// Vertices of the computed mesh (0 before compute()).
  int vertices() const;
  /// Milliseconds of the last compute(): setup (standard triangles, assembly) and factorization.
  double ms_setup() const;
  double ms_factorize() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace volspline::lens
