// SPDX-License-Identifier: MIT
#include "core/param/hex_min_quality.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "core/mesh/hex_quality.h"

namespace volspline::param {

namespace {

// Corners whose scaled Jacobian lies this close above the least one join the ascent direction,
// so that a move does not trade the worst corner for its runner-up.
constexpr double kNearActive = 0.02;
// A move is taken only if it raises the least value by more than this (round-off guard).
constexpr double kMinGain = 1e-9;
// A sweep works on the hexes within this much of the least value (and below target).
constexpr double kBand = 0.1;
// Accepted moves of one node per visit.
constexpr int kStepsPerVisit = 4;
// The sweeps stop once the least value has not risen by kStallGain for kStallSweeps sweeps.
constexpr double kStallGain = 1e-3;
constexpr int kStallSweeps = 20;
// MinQualityOptions::max_edge by default: this times the node's longest edge on entry.
constexpr double kMaxStretch = 3.0;

// One corner of one hex that a node's position changes: hex h's corner c, and which of the
// corner's 4 nodes the node is (0: the corner itself, a + 1: its neighbour along axis a); or
// the hex's centre (corner kCentre, mesh::hex_scaled_jacobian's principal axes), role the node's
// place q in the hex.
constexpr int kCentre = 8;
constexpr int kTouchesPerHex = 5;
struct Touch {
  int hex;
  int corner;
  int role;
};

// Edge a of corner c of a hex, pointing along +axis (mesh::hex_min_scaled_jacobian's convention).
Eigen::Vector3d corner_edge(const std::array<int, 8>& hex, const mesh::Positions& xyz, int c, int a) {
  const int o = c ^ (1 << a);
  const Eigen::Vector3d d = (xyz.row(hex[o]) - xyz.row(hex[c])).transpose();
  return (c >> a & 1) ? Eigen::Vector3d(-d) : d;
}

// Scaled Jacobian of a corner (or the centre) and, if asked, its gradient with respect to the
// node in `role`.
double corner_value(const std::array<int, 8>& hex, const mesh::Positions& xyz, int c, int role,
                    Eigen::Vector3d* gradient) {
  std::array<Eigen::Vector3d, 3> e;
  if (c == kCentre) {
    std::array<Eigen::Vector3d, 8> x;
    for (int q = 0; q < 8; ++q) x[q] = xyz.row(hex[q]).transpose();
    const Eigen::Matrix3d axes = mesh::hex_principal_axes(x);
    for (int a = 0; a < 3; ++a) e[a] = axes.col(a);
  } else {
    e = {corner_edge(hex, xyz, c, 0), corner_edge(hex, xyz, c, 1), corner_edge(hex, xyz, c, 2)};
  }
  const std::array<double, 3> l2 = {e[0].squaredNorm(), e[1].squaredNorm(), e[2].squaredNorm()};
  const double length2 = l2[0] * l2[1] * l2[2];
  if (!(length2 > 0.0)) {
    if (gradient) gradient->setZero();
    return -1.0;
  }
  const double inv_length = 1.0 / std::sqrt(length2);
  const Eigen::Vector3d cofactor0 = e[1].cross(e[2]);
  const double value = e[0].dot(cofactor0) * inv_length;
  if (gradient) {
    // ∂SJ/∂e_a = (e_b × e_c)/L − SJ e_a/|e_a|²; e_a = ±(x_neighbour − x_corner).
    auto d_edge = [&](int a) -> Eigen::Vector3d {
      const Eigen::Vector3d cofactor = a == 0 ? cofactor0 : a == 1 ? e[2].cross(e[0]) : e[0].cross(e[1]);
      return cofactor * inv_length - (value / l2[a]) * e[a];
    };
    auto sign = [&](int a) { return (c >> a & 1) ? -1.0 : 1.0; };
    if (c == kCentre) {
      // ∂e_a/∂x_q = +1 if node q is at the axis's far end, −1 at its near end.
      gradient->setZero();
      for (int a = 0; a < 3; ++a) *gradient += ((role >> a & 1) ? 1.0 : -1.0) * d_edge(a);
    } else if (role == 0) {
      *gradient = -(sign(0) * d_edge(0) + sign(1) * d_edge(1) + sign(2) * d_edge(2));
    } else {
      const int a = role - 1;
      *gradient = sign(a) * d_edge(a);
    }
  }
  return value;
}

// The least-norm point of the convex hull of g (Frank–Wolfe with exact line search): the
// steepest ascent direction of the least of the functions whose gradients they are.
Eigen::Vector3d least_norm_point(const std::vector<Eigen::Vector3d>& g) {
  std::size_t start = 0;
  for (std::size_t i = 1; i < g.size(); ++i)
    if (g[i].squaredNorm() < g[start].squaredNorm()) start = i;
  Eigen::Vector3d d = g[start];
  for (int it = 0; it < 64; ++it) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < g.size(); ++i)
      if (g[i].dot(d) < g[best].dot(d)) best = i;
    const Eigen::Vector3d diff = d - g[best];
    const double gap = diff.dot(d);
    if (gap <= 1e-14 * std::max(1.0, d.squaredNorm())) break;
    const double t = std::clamp(gap / diff.squaredNorm(), 0.0, 1.0);
    d -= t * diff;
  }
  return d;
}

}  // namespace

namespace {

// Per node of the hexes, the longest (or shortest) of its hex edges; `none` for a node in no hex.
std::vector<double> extreme_hex_edges(const std::vector<std::array<int, 8>>& hexes, const mesh::Positions& xyz,
                                      bool longest, double none) {
  std::vector<double> out(xyz.rows(), none);
  auto keep = [&](int v, double l) { out[v] = longest ? std::max(out[v], l) : std::min(out[v], l); };
  for (const auto& hex : hexes)
    for (int c = 0; c < 8; ++c)
      for (int a = 0; a < 3; ++a)
        if (!(c >> a & 1)) {
          const double l = (xyz.row(hex[c ^ (1 << a)]) - xyz.row(hex[c])).norm();
          keep(hex[c], l);
          keep(hex[c ^ (1 << a)], l);
        }
  return out;
}

}  // namespace

std::vector<double> longest_hex_edges(const std::vector<std::array<int, 8>>& hexes, const mesh::Positions& xyz) {
  return extreme_hex_edges(hexes, xyz, true, 0.0);
}

std::vector<double> shortest_hex_edges(const std::vector<std::array<int, 8>>& hexes, const mesh::Positions& xyz) {
  return extreme_hex_edges(hexes, xyz, false, std::numeric_limits<double>::infinity());
}

MinQualityReport raise_min_scaled_jacobian(const std::vector<std::array<int, 8>>& hexes, const std::vector<char>& fixed,
                                           mesh::Positions& xyz, const MinQualityOptions& options,
                                           const SlidingNodes* sliding, const Progress& progress) {
  assert(static_cast<Eigen::Index>(fixed.size()) == xyz.rows());
  if (!(options.target > -1.0 && options.target <= 1.0) || options.max_sweeps < 1 || !(options.first_step > 0.0) ||
      options.first_step > 1.0 || options.halvings < 0)
    throw Error("MinQualityOptions: target in (-1, 1], max_sweeps >= 1, first_step in (0, 1], halvings >= 0");
  if (!options.max_edge.empty() && static_cast<Eigen::Index>(options.max_edge.size()) != xyz.rows())
    throw Error("MinQualityOptions: max_edge has one value per node or none");
  if (!options.min_edge.empty() && static_cast<Eigen::Index>(options.min_edge.size()) != xyz.rows())
    throw Error("MinQualityOptions: min_edge has one value per node or none");
  const int n = static_cast<int>(xyz.rows());
  // Per node, the corners its position changes: in each of its hexes its own corner and the
  // corners of its three neighbours along the hex's edges.
  std::vector<int> touch_begin(n + 1, 0);
  for (const auto& hex : hexes)
    for (int v : hex) touch_begin[v + 1] += kTouchesPerHex;
  for (int v = 0; v < n; ++v) touch_begin[v + 1] += touch_begin[v];
  std::vector<Touch> touches(touch_begin[n]);
  {
    std::vector<int> fill(touch_begin.begin(), touch_begin.end() - 1);
    for (std::size_t h = 0; h < hexes.size(); ++h)
      for (int q = 0; q < 8; ++q) {
        const int v = hexes[h][q];
        touches[fill[v]++] = {static_cast<int>(h), q, 0};
        for (int a = 0; a < 3; ++a) touches[fill[v]++] = {static_cast<int>(h), q ^ (1 << a), a + 1};
        touches[fill[v]++] = {static_cast<int>(h), kCentre, q};
      }
  }
  auto hex_value = [&](std::size_t h) {
    std::array<Eigen::Vector3d, 8> x;
    for (int q = 0; q < 8; ++q) x[q] = xyz.row(hexes[h][q]).transpose();
    return mesh::hex_scaled_jacobian(x);
  };
  // True if every corner the node changes is above `floor` (stops at the first that is not);
  // order: the node's touches, the lowest corners first, so that a failing trial stops early.
  std::vector<int> order;
  // Each value it computes is written to trial_corners[t − first] (first: the node's first touch),
  // so that a trial that passes leaves the next visit step every corner value of the new position.
  std::vector<double> trial_corners;
  auto star_above = [&](double floor, int first) {
    for (const int t : order) {
      const double q = corner_value(hexes[touches[t].hex], xyz, touches[t].corner, touches[t].role, nullptr);
      trial_corners[t - first] = q;
      if (!(q > floor)) return false;
    }
    return true;
  };
  std::vector<double> reach = options.max_edge;
  if (reach.empty()) {
    reach = longest_hex_edges(hexes, xyz);
    for (double& l : reach) l *= kMaxStretch;
  }
  // True if the node's hex edges (its own corners' three edges in each of its hexes) are within
  // reach and not below min_edge.
  auto edges_within = [&](int v) {
    double longest2 = 0.0, shortest2 = std::numeric_limits<double>::infinity();
    for (int t = touch_begin[v]; t < touch_begin[v + 1]; ++t)
      if (touches[t].role == 0 && touches[t].corner != kCentre)
        for (int a = 0; a < 3; ++a) {
          const double l2 = corner_edge(hexes[touches[t].hex], xyz, touches[t].corner, a).squaredNorm();
          longest2 = std::max(longest2, l2);
          shortest2 = std::min(shortest2, l2);
        }
    return std::sqrt(longest2) <= reach[v] && (options.min_edge.empty() || std::sqrt(shortest2) >= options.min_edge[v]);
  };

  // Every hex's least corner value, kept up to date as nodes move.
  std::vector<double> value(hexes.size());
  for (std::size_t h = 0; h < hexes.size(); ++h) value[h] = hex_value(h);
  auto census = [&](double* least) {
    *least = 1.0;
    int below = 0;
    for (const double q : value) {
      *least = std::min(*least, q);
      below += q < options.target;
    }
    return below;
  };

  MinQualityReport report;
  report.below_before = census(&report.min_before);
  std::vector<char> work(n);
  std::vector<Eigen::Vector3d> gradients;
  std::vector<double> corners;  // the value of each corner the node changes, in touch order
  // A visit's outcome depends only on the positions of the nodes of the node's hexes (and on the
  // band when the node's least value is above it), so a node that could not move is skipped
  // until one of its hexes changes: moved[h] is the move count when a node of hex h last moved,
  // stuck[v] the move count when node v last could not move (−1: it could) and stuck_least[v]
  // its least corner value then (+∞ if the band did not stop it). The same moves, fewer visits.
  long long clock = 0;
  std::vector<long long> moved(hexes.size(), 0), stuck(n, -1);
  std::vector<double> stuck_least(n, 0.0);
  double best = report.min_before;
  int stalled = 0;
  for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
    // The free nodes of the hexes within kBand of the least value (and below target), in id
    // order: the sweeps raise the least value rather than spread over every hex below target.
    const double least_now = *std::min_element(value.begin(), value.end());
    if (least_now > best + kStallGain) {
      best = least_now;
      stalled = 0;
    } else if (++stalled > kStallSweeps) {
      break;
    }
    const bool barrier = options.barrier > 0.0;
    const double band = barrier ? options.target : std::min(options.target, least_now + kBand);
    // Barrier mode: a node descends Σ φ(q) over the corners it changes below target, φ(q) =
    // −log a + a − 1 with a = (q − floor)/(target − floor) (C¹, 0 at target), the floor below the
    // sweep's least value by `barrier` times its gap to target.
    const double floor = least_now - options.barrier * (options.target - least_now);
    auto phi = [&](double q) {
      const double a = (q - floor) / (options.target - floor);
      return q >= options.target ? 0.0 : -std::log(a) + a - 1.0;
    };
    auto phi_slope = [&](double q) {
      return q >= options.target ? 0.0 : -1.0 / (q - floor) + 1.0 / (options.target - floor);
    };
    auto star_energy = [&](int v) {
      double e = 0.0;
      for (int t = touch_begin[v]; t < touch_begin[v + 1]; ++t) {
        const double q = corner_value(hexes[touches[t].hex], xyz, touches[t].corner, touches[t].role, nullptr);
        trial_corners[t - touch_begin[v]] = q;
        if (!(q > floor)) return std::numeric_limits<double>::infinity();
        e += phi(q);
      }
      return e;
    };
    std::fill(work.begin(), work.end(), 0);
    bool any = false;
    for (std::size_t h = 0; h < hexes.size(); ++h)
      if (value[h] < band)
        for (int v : hexes[h])
          if (!fixed[v]) work[v] = 1, any = true;
    if (!any) break;
    int moves = 0;
    for (int v = 0; v < n; ++v) {
      if (!work[v]) continue;
      if (stuck[v] >= 0 && stuck_least[v] >= band) {
        bool changed = false;
        for (int t = touch_begin[v]; t < touch_begin[v + 1] && !changed; t += kTouchesPerHex) changed = moved[touches[t].hex] > stuck[v];
        if (!changed) continue;
      }
      stuck[v] = -1;
      bool moved_here = false;
      trial_corners.resize(touch_begin[v + 1] - touch_begin[v]);
      // After an accepted move, the corner values of the new position are those of its trial.
      bool known = false;
      for (int visit = 0; visit < kStepsPerVisit; ++visit) {
        // The least value over the node's corners (gradients below, of the near-least ones only).
        double least = std::numeric_limits<double>::infinity();
        double shortest2 = std::numeric_limits<double>::infinity();
        if (known)
          corners.swap(trial_corners);
        else
          corners.clear();
        for (int t = touch_begin[v]; t < touch_begin[v + 1]; ++t) {
          const Touch& touch = touches[t];
          if (!known) corners.push_back(corner_value(hexes[touch.hex], xyz, touch.corner, touch.role, nullptr));
          const double corner = corners[t - touch_begin[v]];
          least = std::min(least, corner);
          if (touch.role > 0 && touch.corner != kCentre)
            shortest2 = std::min(shortest2, corner_edge(hexes[touch.hex], xyz, touch.corner, touch.role - 1).squaredNorm());
        }
        stuck[v] = clock;
        stuck_least[v] = least;
        if (least >= band) break;
        stuck_least[v] = std::numeric_limits<double>::infinity();
        const double shortest = std::sqrt(shortest2);
        Eigen::Matrix3d tangent = Eigen::Matrix3d::Identity();
        const bool slides = sliding && sliding->slides[v];
        const Eigen::Vector3d x0 = xyz.row(v).transpose();
        if (slides) sliding->project(v, x0, &tangent);
        gradients.clear();
        order.clear();
        Eigen::Vector3d direction = Eigen::Vector3d::Zero();
        double energy = 0.0;
        if (barrier) {
          for (int t = touch_begin[v]; t < touch_begin[v + 1]; ++t) {
            const double q = corners[t - touch_begin[v]];
            if (q >= options.target) continue;
            Eigen::Vector3d g;
            corner_value(hexes[touches[t].hex], xyz, touches[t].corner, touches[t].role, &g);
            energy += phi(q);
            direction -= phi_slope(q) * (tangent * g);
          }
        } else {
          for (int t = touch_begin[v]; t < touch_begin[v + 1]; ++t)
            if (corners[t - touch_begin[v]] <= least + kNearActive) {
              Eigen::Vector3d g;
              corner_value(hexes[touches[t].hex], xyz, touches[t].corner, touches[t].role, &g);
              gradients.push_back(tangent * g);
              order.push_back(t);
            }
          for (int t = touch_begin[v]; t < touch_begin[v + 1]; ++t)
            if (!(corners[t - touch_begin[v]] <= least + kNearActive)) order.push_back(t);
          direction = least_norm_point(gradients);
        }
        const double norm = direction.norm();
        if (!(norm > 1e-12) || !(shortest > 0.0) || !std::isfinite(shortest)) break;
        direction /= norm;
        double step = options.first_step * shortest;
        bool moved = false;
        for (int k = 0; k <= options.halvings && !moved; ++k, step *= 0.5) {
          const Eigen::Vector3d trial = x0 + step * direction;
          const Eigen::Vector3d p = slides ? sliding->project(v, trial, nullptr) : trial;
          xyz.row(v) = p.transpose();
          moved = (barrier ? star_energy(v) < energy - 1e-12 * energy : star_above(least + kMinGain, touch_begin[v])) &&
                  edges_within(v);
          if (!moved) xyz.row(v) = x0.transpose();
        }
        if (!moved) break;
        known = true;
        ++moves;
        moved_here = true;
        ++clock;
        stuck[v] = -1;
      }
      if (moved_here)
        for (int t = touch_begin[v]; t < touch_begin[v + 1]; t += kTouchesPerHex) {
          value[touches[t].hex] = hex_value(touches[t].hex);
          moved[touches[t].hex] = clock;
        }
    }
    report.sweeps = sweep + 1;
    report.moves += moves;
    progress.report("grid quality", static_cast<double>(sweep + 1) / options.max_sweeps);
    if (moves == 0) break;
  }
  report.below_after = census(&report.min_after);
  return report;
}

}  // namespace volspline::param
