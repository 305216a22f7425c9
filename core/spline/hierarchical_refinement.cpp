// SPDX-License-Identifier: MIT
#include "core/spline/hierarchical_refinement.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <map>
#include <tuple>
#include <unordered_map>

#include "core/spline/knot_insertion.h"

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

void RefinementGrid::collect_planes(int id, int axis, const Eigen::Vector3d& anchor,
                                    std::vector<double>& planes) const {
  const Node& node = nodes_[id];
  for (int b = 0; b < 3; ++b)
    if (b != axis && (anchor(b) < node.lo(b) || anchor(b) > node.hi(b))) return;
  if (node.first_child < 0) {
    planes.push_back(node.lo(axis));
    planes.push_back(node.hi(axis));
    return;
  }
  for (int c = 0; c < 8; ++c) collect_planes(node.first_child + c, axis, anchor, planes);
}

std::vector<double> RefinementGrid::line_planes(int axis, const Eigen::Vector3d& anchor) const {
  std::vector<double> planes;
  // Only the roots whose closed box holds the anchor in the two other axes meet the ray.
  std::array<std::array<int, 2>, 3> range;
  for (int b = 0; b < 3; ++b) {
    if (b == axis) {
      range[b] = {0, cells_[b] - 1};
      continue;
    }
    const double t = (anchor(b) - lo_(b)) / (hi_(b) - lo_(b)) * cells_[b];
    const int i = std::clamp(static_cast<int>(std::floor(t)), 0, cells_[b] - 1);
    range[b] = {std::max(0, i - 1), std::min(cells_[b] - 1, i + 1)};
  }
  for (int k = range[2][0]; k <= range[2][1]; ++k)
    for (int j = range[1][0]; j <= range[1][1]; ++j)
      for (int i = range[0][0]; i <= range[0][1]; ++i)
        collect_planes(i + cells_[0] * (j + cells_[1] * k), axis, anchor, planes);
  std::sort(planes.begin(), planes.end());
  planes.erase(std::unique(planes.begin(), planes.end()), planes.end());
  return planes;
}

LocalKnots RefinementGrid::knots_on_line(const std::vector<double>& planes, int axis, double centre) const {
  LocalKnots r;
  r[2] = centre;
  auto above = std::upper_bound(planes.begin(), planes.end(), centre);
  for (int k = 3; k <= 4; ++k) {
    r[k] = above != planes.end() ? *above : std::min(hi_(axis), std::max(centre, r[k - 1]));
    if (above != planes.end()) ++above;
  }
  auto below = std::lower_bound(planes.begin(), planes.end(), centre);
  for (int k = 1; k >= 0; --k) {
    if (below != planes.begin()) {
      --below;
      r[k] = *below;
    } else {
      r[k] = std::max(lo_(axis), std::min(centre, r[k + 1]));
    }
  }
  return r;
}

LocalKnots RefinementGrid::ray_knots(const BlendingKnots& knots, int axis) const {
  // §4.2.2 ray tracing: from the anchor (the central knots), the first two faces of the T-mesh
  // crossed in each direction along `axis`; at the domain ends the boundary knots repeat.
  const Eigen::Vector3d anchor(knots[0][2], knots[1][2], knots[2][2]);
  return knots_on_line(line_planes(axis, anchor), axis, anchor(axis));
}

TSpline RefinementGrid::split(const TSpline& spline, const std::vector<int>& leaf_ids,
                              TSplineAcceleration acceleration) {
  Functions refined = split_functions({spline.knots(), spline.weights(), spline.points()}, leaf_ids);
  return TSpline(std::move(refined.knots), std::move(refined.weights), std::move(refined.points), acceleration);
}

RefinementGrid::Functions RefinementGrid::split_functions(const Functions& functions, const std::vector<int>& leaf_ids) {
  for (int id : leaf_ids) {
    assert(nodes_[id].first_child < 0);
    const Node parent = nodes_[id];
    const Eigen::Vector3d mid = 0.5 * (parent.lo + parent.hi);
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
  // §4.3.3 steps 2–3: every blending function takes the knots its ray-traced vector R* in the
  // refined T-mesh has and its own R lacks (Eq. 4.8/4.9), until nothing changes; then blending
  // functions with identical knots are collected into one with the total weight. Done on plain
  // arrays so that the evaluation grid of the spline is built once.
  struct Function {
    BlendingKnots knots;
    double weight;
    Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, 4, 1> weighted_point;  // w p, so that merging is a plain sum
  };
  const int n = static_cast<int>(functions.knots.size());
  const Eigen::Index dimension = functions.points.cols();
  assert(dimension >= 1 && dimension <= 4);
  std::vector<Function> work;
  work.reserve(n);
  for (int i = 0; i < n; ++i)
    work.push_back({functions.knots[i], functions.weights(i),
                    functions.weights(i) * functions.points.row(i).transpose()});
  std::vector<Function> done;
  std::unordered_map<BlendingKnots, int, KnotsHash> index;  // knots -> position in `done`
  // The T-mesh faces a ray crosses depend only on its line (axis and the two other anchor
  // coordinates), and many blending functions share a line: the planes are traced once per line.
  std::map<std::tuple<int, double, double>, std::vector<double>> line_cache;
  auto cached_ray_knots = [&](const BlendingKnots& knots, int axis) {
    const Eigen::Vector3d anchor(knots[0][2], knots[1][2], knots[2][2]);
    const auto key = std::make_tuple(axis, anchor((axis + 1) % 3), anchor((axis + 2) % 3));
    auto it = line_cache.find(key);
    if (it == line_cache.end()) it = line_cache.emplace(key, line_planes(axis, anchor)).first;
    return knots_on_line(it->second, axis, anchor(axis));
  };
  while (!work.empty()) {
    Function f = std::move(work.back());
    work.pop_back();
    int axis = -1;
    double knot = 0.0;
    for (int a = 0; a < 3 && axis < 0; ++a) {
      const LocalKnots& r = f.knots[a];
      for (double k : cached_ray_knots(f.knots, a))
        if (r[0] < k && k < r[4] && std::find(r.begin(), r.end(), k) == r.end()) {
          axis = a;
          knot = k;
          break;
        }
    }
    if (axis < 0) {
      const auto found = index.find(f.knots);
      if (found == index.end()) {
        index.emplace(f.knots, static_cast<int>(done.size()));
        done.push_back(std::move(f));
      } else {
        done[found->second].weight += f.weight;
        done[found->second].weighted_point += f.weighted_point;
      }
      continue;
    }
    const BlendingSplit split = split_blending_function(f.knots, axis, knot);
    // Eq. 4.9: w B = (w c1) B1 + (w c2) B2, with the same control point.
    if (split.second_coefficient > 0.0)
      work.push_back({split.second, f.weight * split.second_coefficient,
                      split.second_coefficient * f.weighted_point});
    if (split.first_coefficient > 0.0)
      work.push_back({split.first, f.weight * split.first_coefficient,
                      split.first_coefficient * f.weighted_point});
  }
  // Deterministic order: sorted by knot vectors (distinct, so no ties).
  std::vector<int> order(done.size());
  for (std::size_t p = 0; p < done.size(); ++p) order[p] = static_cast<int>(p);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return done[a].knots < done[b].knots; });
  std::vector<BlendingKnots> knots;
  Eigen::VectorXd weights(static_cast<Eigen::Index>(done.size()));
  Eigen::MatrixXd points(static_cast<Eigen::Index>(done.size()), dimension);
  knots.reserve(done.size());
  int row = 0;
  for (int position : order) {
    const Function& f = done[position];
    knots.push_back(f.knots);
    weights(row) = f.weight;
    points.row(row) = (f.weighted_point / f.weight).transpose();
    ++row;
  }
  return {std::move(knots), std::move(weights), std::move(points)};
}

}  // namespace volspline::spline
