// SPDX-License-Identifier: MIT
#include "core/lens/flatten.h"

#include "core/lens/lens_flattener.h"

namespace volspline::lens {

FlattenResult flatten_lens(const mesh::Positions& xyz, const mesh::Triangles& triangles,
                           const std::vector<char>& pinned, const Eigen::MatrixX2d& start,
                           const FlattenOptions& options, const Progress& progress) {
  LensFlattener flattener;
  flattener.compute(xyz, triangles, pinned, options.height_unit);
  return flattener.flatten(start, options, progress);
}

}  // namespace volspline::lens
