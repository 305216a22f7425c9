// SPDX-License-Identifier: MIT
#include "core/spline/hierarchical_refinement.h"

#include <algorithm>
#include <cassert>

#include "core/spline/tspline_refinement.h"

namespace volspline::spline {

RefinementGrid::RefinementGrid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                               std::array<int, 3> cells)
    : lo_(lo), hi_(hi), cells_(cells) {
  assert(cells[0] >= 1 && cells[1] >= 1 && cells[2] >= 1);
  assert((lo.array() < hi.array()).all());
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i) {
        Node node;
        const std::array<int, 3> ijk = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          node.lo(a) = lo(a) + (hi(a) - lo(a)) * ijk[a] / cells[a];
          node.hi(a) = ijk[a] + 1 == cells[a] ? hi(a) : lo(a) + (hi(a) - lo(a)) * (ijk[a] + 1) / cells[a];
        }
        nodes_.push_back(node);
      }
  num_leaves_ = static_cast<int>(nodes_.size());
}

std::vector<int> RefinementGrid::leaves() const {
  std::vector<int> ids;
  ids.reserve(num_leaves_);
  for (int id = 0; id < static_cast<int>(nodes_.size()); ++id)
    if (nodes_[id].first_child < 0) ids.push_back(id);
  return ids;
}

int RefinementGrid::leaf_of(const Eigen::Vector3d& uvw) const {
  std::array<int, 3> ijk;
  for (int a = 0; a < 3; ++a) {
    const double t = (uvw(a) - lo_(a)) / (hi_(a) - lo_(a));
    ijk[a] = std::clamp(static_cast<int>(t * cells_[a]), 0, cells_[a] - 1);
  }
  int id = ijk[0] + cells_[0] * (ijk[1] + cells_[1] * ijk[2]);
  while (nodes_[id].first_child >= 0) {
    const Node& node = nodes_[id];
    int c = 0;
    for (int a = 0; a < 3; ++a)
      if (uvw(a) >= 0.5 * (node.lo(a) + node.hi(a))) c |= 1 << a;
    id = node.first_child + c;
  }
  return id;
}

TSpline RefinementGrid::split(const TSpline& spline, const std::vector<int>& leaf_ids) {
  const int n = spline.num_functions();
  std::vector<NewKnots> new_knots(n);
  for (int id : leaf_ids) {
    assert(nodes_[id].first_child < 0);
    const Eigen::Vector3d lo = nodes_[id].lo, hi = nodes_[id].hi;
    const Eigen::Vector3d mid = 0.5 * (lo + hi);
    for (int i = 0; i < n; ++i) {
      const BlendingKnots& knots = spline.knots()[i];
      bool overlaps = true;
      for (int a = 0; a < 3 && overlaps; ++a)
        overlaps = knots[a][0] < hi(a) && knots[a][4] > lo(a);
      if (!overlaps) continue;
      for (int a = 0; a < 3; ++a) {
        const LocalKnots& r = knots[a];
        // Eq. 4.8 needs r0 < k < r4; an existing knot would only raise its multiplicity.
        if (!(r[0] < mid(a) && mid(a) < r[4])) continue;
        if (std::find(r.begin(), r.end(), mid(a)) != r.end()) continue;
        auto& list = new_knots[i][a];
        if (std::find(list.begin(), list.end(), mid(a)) == list.end()) list.push_back(mid(a));
      }
    }
    Node parent = nodes_[id];
    nodes_[id].first_child = static_cast<int>(nodes_.size());
    for (int c = 0; c < 8; ++c) {
      Node child;
      child.level = parent.level + 1;
      for (int a = 0; a < 3; ++a) {
        const bool upper = (c >> a) & 1;
        child.lo(a) = upper ? mid(a) : parent.lo(a);
        child.hi(a) = upper ? parent.hi(a) : mid(a);
      }
      nodes_.push_back(child);
    }
    num_leaves_ += 7;
    max_level_ = std::max(max_level_, parent.level + 1);
  }
  for (auto& knots : new_knots)
    for (auto& list : knots) std::sort(list.begin(), list.end());
  return refine_blending_functions(spline, new_knots);
}

}  // namespace volspline::spline
