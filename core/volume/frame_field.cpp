// SPDX-License-Identifier: MIT
#include "core/volume/frame_field.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "core/common/error.h"
#include "core/linalg/parallel_for.h"

namespace volspline::volume {

namespace {

// A cube rotation as a signed permutation: (g b)_r = sign[r] * b_{perm[r]}.
struct SignedPermutation {
  std::array<int, 3> perm;
  std::array<double, 3> sign;
};

std::array<SignedPermutation, 24> make_signed_permutations() {
  std::array<SignedPermutation, 24> result{};
  std::array<int, 3> perm{0, 1, 2};
  int count = 0;
  do {
    // Parity of the permutation: the number of inversions.
    int inversions = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) inversions += perm[i] > perm[j];
    for (int signs = 0; signs < 8; ++signs) {
      const std::array<double, 3> sign{(signs & 1) ? -1.0 : 1.0, (signs & 2) ? -1.0 : 1.0, (signs & 4) ? -1.0 : 1.0};
      const double det = sign[0] * sign[1] * sign[2] * (inversions % 2 ? -1.0 : 1.0);
      if (det > 0) result[count++] = {perm, sign};
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  return result;
}

const std::array<SignedPermutation, 24>& signed_permutations() {
  static const std::array<SignedPermutation, 24> table = make_signed_permutations();
  return table;
}

// The 6 permutations in std::next_permutation order and their parity, matching make_signed_permutations.
constexpr int kPermutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
constexpr bool kOddPermutation[6] = {false, true, true, false, false, true};

// Rank of sign pattern `bits` among the valid sign patterns of permutation p, in the order
// make_signed_permutations lists them.
int sign_rank(int p, int bits) {
  int rank = 0;
  for (int other = 0; other < bits; ++other) {
    const int count = (other & 1) + ((other >> 1) & 1) + ((other >> 2) & 1);
    rank += (count % 2 == 1) == kOddPermutation[p];
  }
  return rank;
}

// max over the cube rotations g of tr(a^T g b), i.e. minimizing ||a - g b||_F^2, and (kIndex) the
// permutation p and sign bits attaining it. Per permutation the best signs follow the terms'
// signs; if that breaks det g = +1 the smallest term is flipped. 6 candidates instead of 24; ties
// keep the first permutation found. Hot loop of the smoothing: plain doubles.
template <bool kIndex>
double best_score(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, int* best_p, int* best_bits) {
  double d[3][3];  // d[r][q] = a_r . b_q
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) d[r][q] = a(r, 0) * b(q, 0) + a(r, 1) * b(q, 1) + a(r, 2) * b(q, 2);
  double score = -1e300;
  for (int p = 0; p < 6; ++p) {
    const double t0 = d[0][kPermutations[p][0]], t1 = d[1][kPermutations[p][1]], t2 = d[2][kPermutations[p][2]];
    const double a0 = std::abs(t0), a1 = std::abs(t1), a2 = std::abs(t2);
    double sum = a0 + a1 + a2;
    const bool flip = ((t0 < 0) != (t1 < 0)) != ((t2 < 0) != kOddPermutation[p]);
    if constexpr (kIndex) {
      int bits = (t0 < 0) | ((t1 < 0) << 1) | ((t2 < 0) << 2);
      if (flip) {
        const int smallest = a1 < a0 ? (a2 < a1 ? 2 : 1) : (a2 < a0 ? 2 : 0);
        bits ^= 1 << smallest;
        sum -= 2 * (smallest == 0 ? a0 : smallest == 1 ? a1 : a2);
      }
      if (sum > score) {
        score = sum;
        *best_p = p;
        *best_bits = bits;
      }
    } else {
      if (flip) sum -= 2 * std::min(a0, std::min(a1, a2));
      score = std::max(score, sum);
    }
  }
  return score;
}

// Index of the cube rotation g maximizing tr(a^T g b) (the group index is formed for the winner
// only), and that maximum.
int best_match(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, double& score) {
  int best_p = 0, best_bits = 0;
  score = best_score<true>(a, b, &best_p, &best_bits);
  return 4 * best_p + sign_rank(best_p, best_bits);
}

Eigen::Matrix3d apply(const SignedPermutation& sp, const Eigen::Matrix3d& b) {
  Eigen::Matrix3d result;
  for (int r = 0; r < 3; ++r) result.row(r) = sp.sign[r] * b.row(sp.perm[r]);
  return result;
}

double distance_from_score(double score) { return std::max(0.0, 6.0 - 2.0 * score); }

// Neighbour ids of voxel (x, y, z) in the 6-neighbourhood, in a fixed order; returns the count.
int neighbours(const FrameField& f, int x, int y, int z, std::array<std::size_t, 6>& out) {
  const std::size_t id = static_cast<std::size_t>(x) + static_cast<std::size_t>(f.nx) * (y + static_cast<std::size_t>(f.ny) * z);
  const std::size_t sy = f.nx;
  const std::size_t sz = static_cast<std::size_t>(f.nx) * f.ny;
  int n = 0;
  if (x > 0) out[n++] = id - 1;
  if (x + 1 < f.nx) out[n++] = id + 1;
  if (y > 0) out[n++] = id - sy;
  if (y + 1 < f.ny) out[n++] = id + sy;
  if (z > 0) out[n++] = id - sz;
  if (z + 1 < f.nz) out[n++] = id + sz;
  return n;
}

double local_energy(const Eigen::Matrix3d& frame, const FrameField& f, const std::array<std::size_t, 6>& ids, int n) {
  double energy = 0.0;
  for (int k = 0; k < n; ++k) energy += distance_from_score(best_score<false>(frame, f.frames[ids[k]], nullptr, nullptr));
  return energy;
}

// Index of the frame row closest to the line of unit vector `normal`, and the sign that points it along normal.
int closest_axis(const Eigen::Matrix3d& frame, const Eigen::Vector3d& normal, double& sign) {
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(frame.row(a).dot(normal)) > std::abs(frame.row(axis).dot(normal))) axis = a;
  sign = frame.row(axis).dot(normal) < 0 ? -1.0 : 1.0;
  return axis;
}

// Smallest rotation of the whole frame taking its closest axis onto the normal's line (§5.2.2).
Eigen::Matrix3d project_to_constraint(const Eigen::Matrix3d& frame, const Eigen::Vector3d& normal) {
  double sign = 1.0;
  const int axis = closest_axis(frame, normal, sign);
  const Eigen::Matrix3d q =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d(frame.row(axis)), sign * normal).toRotationMatrix();
  return frame * q.transpose();
}

// Rotation R maximizing tr(R^T m): polar decomposition of m via SVD, reflection removed.
Eigen::Matrix3d polar_rotation_svd(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0) u.col(2) = -u.col(2);
  return u * v.transpose();
}

// Same rotation by the scaled Newton iteration X <- (g X + X^-T / g) / 2 (Higham), several times
// cheaper than a 3x3 SVD; the covariance of matched neighbours is well conditioned with det > 0
// almost always, and anything else goes to the SVD.
Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& m) {
  Eigen::Matrix3d x = m;
  for (int iteration = 0; iteration < 20; ++iteration) {
    const Eigen::Matrix3d cofactor = [&] {
      Eigen::Matrix3d c;
      c.row(0) = x.row(1).cross(x.row(2));
      c.row(1) = x.row(2).cross(x.row(0));
      c.row(2) = x.row(0).cross(x.row(1));
      return c;
    }();
    const double det = x.row(0).dot(cofactor.row(0));
    const double scale = x.squaredNorm();
    if (!(det > 1e-6 * scale * std::sqrt(scale))) return polar_rotation_svd(m);
    // Scaling det(gamma X) = 1 speeds up the first steps; near convergence it is 1 anyway.
    const double gamma = std::abs(det - 1.0) < 1e-3 ? 1.0 : std::cbrt(1.0 / det);
    const Eigen::Matrix3d next = 0.5 * (gamma * x + cofactor / (gamma * det));  // X^-T = cofactor / det
    const double change = (next - x).squaredNorm();
    x = next;
    if (change < 1e-24) return x;
  }
  return polar_rotation_svd(m);
}

// Rotation R with row `axis` = fixed (unit) maximizing tr(R^T m): a 1D rotation about `fixed`
// solved in closed form.
Eigen::Matrix3d constrained_rotation(const Eigen::Matrix3d& m, int axis, const Eigen::Vector3d& fixed) {
  const int b = (axis + 1) % 3;
  const int c = (axis + 2) % 3;
  const Eigen::Vector3d helper = std::abs(fixed.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d t1 = fixed.cross(helper).normalized();
  const Eigen::Vector3d t2 = fixed.cross(t1);
  // Row b = cos(t) t1 + sin(t) t2, row c = fixed x row b = cos(t) t2 - sin(t) t1.
  const Eigen::Vector3d mb = m.row(b).transpose();
  const Eigen::Vector3d mc = m.row(c).transpose();
  const double along_cos = t1.dot(mb) + t2.dot(mc);
  const double along_sin = t2.dot(mb) - t1.dot(mc);
  const double theta = std::atan2(along_sin, along_cos);
  Eigen::Matrix3d r;
  r.row(axis) = fixed.transpose();
  r.row(b) = (std::cos(theta) * t1 + std::sin(theta) * t2).transpose();
  r.row(c) = (std::cos(theta) * t2 - std::sin(theta) * t1).transpose();
  return r;
}

}  // namespace

const std::array<Eigen::Matrix3d, 24>& cube_group_rotations() {
  static const std::array<Eigen::Matrix3d, 24> rotations = [] {
    std::array<Eigen::Matrix3d, 24> result;
    const auto& table = signed_permutations();
    for (int g = 0; g < 24; ++g) result[g] = apply(table[g], Eigen::Matrix3d::Identity());
    return result;
  }();
  return rotations;
}

double frame_distance_squared(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, Eigen::Matrix3d* best) {
  if (!best) return distance_from_score(best_score<false>(a, b, nullptr, nullptr));
  double score = 0.0;
  const int g = best_match(a, b, score);
  if (best) *best = cube_group_rotations()[g];
  return distance_from_score(score);
}

double frame_smoothness_energy(const FrameField& field, const std::vector<std::uint8_t>* active, int threads) {
  // Eq. 5.6 over the 6-neighbour edges, each counted once, with jump matching; one partial sum
  // per z plane, added in plane order (the same bits for every thread count).
  assert(!active || active->size() == field.frames.size());
  const std::size_t sy = field.nx;
  const std::size_t sz = static_cast<std::size_t>(field.nx) * field.ny;
  auto on = [&](std::size_t id) { return !active || (*active)[id] != 0; };
  std::vector<double> plane_energy(static_cast<std::size_t>(std::max(0, field.nz)), 0.0);
  linalg::parallel_for(threads, field.nz, [&](int z) {
    double energy = 0.0;
    for (int y = 0; y < field.ny; ++y)
      for (int x = 0; x < field.nx; ++x) {
        const std::size_t id = x + sy * (y + static_cast<std::size_t>(field.ny) * z);
        if (!on(id)) continue;
        const Eigen::Matrix3d& frame = field.frames[id];
        if (x + 1 < field.nx && on(id + 1)) energy += frame_distance_squared(frame, field.frames[id + 1]);
        if (y + 1 < field.ny && on(id + sy)) energy += frame_distance_squared(frame, field.frames[id + sy]);
        if (z + 1 < field.nz && on(id + sz)) energy += frame_distance_squared(frame, field.frames[id + sz]);
      }
    plane_energy[z] = energy;
  });
  double energy = 0.0;
  for (double e : plane_energy) energy += e;
  return energy;
}

namespace {

// Throws volspline::Error on options out of range, a grid or mask of the wrong size, or an
// active frame that is not a rotation.
void check_smoothing_input(const FrameField& initial, const FrameSmoothingOptions& options) {
  if (options.max_iterations < 1)
    throw Error("frame smoothing: max_iterations must be >= 1, got " + std::to_string(options.max_iterations));
  if (options.threads < 1)
    throw Error("frame smoothing: threads must be >= 1, got " + std::to_string(options.threads));
  if (!(options.energy_decrease_tol_rel >= 0))
    throw Error("frame smoothing: energy_decrease_tol_rel must be >= 0");
  if (initial.nx < 1 || initial.ny < 1 || initial.nz < 1)
    throw Error("frame smoothing: grid dimensions must be positive");
  const std::size_t n = static_cast<std::size_t>(initial.nx) * initial.ny * initial.nz;
  if (initial.frames.size() != n)
    throw Error("frame smoothing: " + std::to_string(initial.frames.size()) + " frames for a grid of " + std::to_string(n) + " voxels");
  if (!options.active.empty() && options.active.size() != n)
    throw Error("frame smoothing: active mask has " + std::to_string(options.active.size()) + " entries for a grid of " +
                std::to_string(n) + " voxels");
  for (std::size_t i = 0; i < n; ++i) {
    if (!options.active.empty() && options.active[i] == 0) continue;
    const Eigen::Matrix3d& f = initial.frames[i];
    if (!f.allFinite() || (f * f.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 || f.determinant() < 0)
      throw Error("frame smoothing: frame of voxel " + std::to_string(i) + " is not a rotation");
  }
}

// The constraints of the active voxels: per voxel an index into `normals` (unit) or -1.
struct ConstraintIndex {
  std::vector<int> constraint_of;
  std::vector<Eigen::Vector3d> normals;
};

// Throws volspline::Error on a constraint outside the grid, a zero normal or a voxel constrained twice.
ConstraintIndex index_constraints(const std::vector<FrameConstraint>& constraints, std::size_t n,
                                  const std::vector<std::uint8_t>* active) {
  ConstraintIndex index;
  index.constraint_of.assign(n, -1);
  for (const FrameConstraint& c : constraints) {
    if (c.voxel_id >= n)
      throw Error("frame smoothing: constraint voxel " + std::to_string(c.voxel_id) + " is outside the grid of " + std::to_string(n) + " voxels");
    if (!c.normal.allFinite() || !(c.normal.norm() > 0))
      throw Error("frame smoothing: constraint normal of voxel " + std::to_string(c.voxel_id) + " is zero or not finite");
    if (index.constraint_of[c.voxel_id] >= 0)
      throw Error("frame smoothing: voxel " + std::to_string(c.voxel_id) + " has more than one constraint");
    if (active && (*active)[c.voxel_id] == 0) continue;
    index.constraint_of[c.voxel_id] = static_cast<int>(index.normals.size());
    index.normals.push_back(c.normal.normalized());
  }
  return index;
}

// An active voxel with its active 6-neighbours.
struct Node {
  std::size_t id;
  int count;
  std::array<std::size_t, 6> ids;
};

// The active voxels in voxel order.
std::vector<Node> active_nodes(const FrameField& field, const std::vector<std::uint8_t>* active) {
  auto is_active = [&](std::size_t id) { return !active || (*active)[id] != 0; };
  std::vector<Node> nodes;
  nodes.reserve(active ? field.frames.size() / 4 : field.frames.size());
  std::array<std::size_t, 6> ids{};
  for (int z = 0; z < field.nz; ++z)
    for (int y = 0; y < field.ny; ++y)
      for (int x = 0; x < field.nx; ++x) {
        const std::size_t id = static_cast<std::size_t>(x) + static_cast<std::size_t>(field.nx) * (y + static_cast<std::size_t>(field.ny) * z);
        if (!is_active(id)) continue;
        Node node{id, 0, {}};
        const int count = neighbours(field, x, y, z, ids);
        for (int k = 0; k < count; ++k)
          if (is_active(ids[k])) node.ids[node.count++] = ids[k];
        nodes.push_back(node);
      }
  return nodes;
}

// FrameInitialization::Propagated. Deviation (Given is the thesis): the Hessian frames of flat
// or step-like regions are defined only up to a rotation about one axis, set by round-off, and
// Gauss-Seidel keeps the twists they start with; growing the field from the iso-surface
// constraints (breadth first, each voxel the polar factor of its grown neighbours' matched
// frames) starts it without them.
void propagate_from_constraints(const std::vector<Node>& nodes, const std::vector<int>& constraint_of, FrameField& field) {
  const auto& table = signed_permutations();
  std::vector<int> slot_of(field.frames.size(), -1);
  for (std::size_t s = 0; s < nodes.size(); ++s) slot_of[nodes[s].id] = static_cast<int>(s);
  std::vector<std::uint8_t> queued(nodes.size(), 0), grown(nodes.size(), 0);
  std::vector<std::size_t> queue;
  for (std::size_t s = 0; s < nodes.size(); ++s)
    if (constraint_of[nodes[s].id] >= 0) {
      queue.push_back(s);
      queued[s] = 1;
    }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const Node& node = nodes[queue[head]];
    if (constraint_of[node.id] < 0) {
      const Eigen::Matrix3d* reference = nullptr;
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (int k = 0; k < node.count; ++k) {
        if (!grown[slot_of[node.ids[k]]]) continue;
        const Eigen::Matrix3d& other = field.frames[node.ids[k]];
        if (!reference) reference = &other;
        double score = 0.0;
        covariance += apply(table[best_match(*reference, other, score)], other);
      }
      field.frames[node.id] = polar_rotation(covariance);
    }
    grown[queue[head]] = 1;
    for (int k = 0; k < node.count; ++k) {
      const int s = slot_of[node.ids[k]];
      if (!queued[s]) {
        queued[s] = 1;
        queue.push_back(static_cast<std::size_t>(s));
      }
    }
  }
}

// Kahan sum of the energy decrease of one slab.
struct Decrease {
  double sum = 0.0;
  double carry = 0.0;
  void add(double value) {
    const double term = value - carry;
    const double next = sum + term;
    carry = (next - sum) - term;
    sum = next;
  }
};

// The sweeps of smooth_frame_field. Slab ordering (§5.2.2 sweeps in voxel order; deviation: the
// grid is cut into slabs of kSlabPlanes z planes, swept in voxel order inside each slab, forward
// and backward in turn as symmetric Gauss-Seidel; slabs of one parity only touch slabs of the
// other, so the even slabs run in parallel, then the odd ones (reversed on backward sweeps), with
// the same result for every thread count).
class SlabSweeper {
 public:
  SlabSweeper(FrameField& field, const std::vector<Node>& nodes, const ConstraintIndex& constraints)
      : field_(field), nodes_(nodes), constraints_(constraints), num_slabs_((field.nz + kSlabPlanes - 1) / kSlabPlanes),
        slab_begin_(static_cast<std::size_t>(num_slabs_) + 1, nodes.size()), changed_at_(field.frames.size(), 1),
        visited_at_(field.frames.size(), 0), slab_decrease_(static_cast<std::size_t>(num_slabs_)) {
    const std::size_t plane = static_cast<std::size_t>(field.nx) * field.ny;
    for (std::size_t s = nodes.size(); s-- > 0;) slab_begin_[nodes[s].id / plane / kSlabPlanes] = s;
    for (int slab = num_slabs_; slab-- > 0;) slab_begin_[slab] = std::min(slab_begin_[slab], slab_begin_[slab + 1]);
  }

  // One sweep (forward on odd iterations, backward on even ones); returns the energy decrease,
  // the slab sums added in slab order (the same bits for every thread count).
  double sweep(int iteration, int threads) {
    const bool forward = iteration % 2 == 1;
    std::fill(slab_decrease_.begin(), slab_decrease_.end(), Decrease{});
    for (int half = 0; half < 2; ++half) {
      const int parity = forward ? half : 1 - half;
      ++half_sweep_;
      linalg::parallel_for(threads, (num_slabs_ + 1 - parity) / 2, [&](int k) {
        const int slab = 2 * k + parity;
        const std::size_t begin = slab_begin_[slab], end = slab_begin_[slab + 1];
        for (std::size_t step = 0; step < end - begin; ++step) {
          const std::uint64_t clock = (half_sweep_ << 32) + step + 1;
          update_voxel(nodes_[forward ? begin + step : end - 1 - step], clock, slab_decrease_[slab]);
        }
      });
    }
    Decrease sweep_decrease;
    for (const Decrease& d : slab_decrease_) sweep_decrease.add(d.sum);
    return sweep_decrease.sum;
  }

 private:
  static constexpr int kSlabPlanes = 4;

  void update_voxel(const Node& node, std::uint64_t clock, Decrease& decrease) {
    const std::size_t id = node.id;
    const int count = node.count;
    bool stale = changed_at_[id] >= visited_at_[id];
    for (int k = 0; k < count && !stale; ++k) stale = changed_at_[node.ids[k]] > visited_at_[id];
    if (!stale) return;
    visited_at_[id] = clock;
    const Eigen::Matrix3d current = field_.frames[id];
    // Jump matching: each neighbour's frame end points are relabelled by the cube rotation that
    // best fits them to ours; the covariance of the matched end points (+-f_r against +-g f'_r)
    // is twice the sum of the matched frames, so the registration rotation is its polar factor.
    const auto& table = signed_permutations();
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    double old_energy = 0.0;
    for (int k = 0; k < count; ++k) {
      double score = 0.0;
      const int g = best_match(current, field_.frames[node.ids[k]], score);
      covariance += apply(table[g], field_.frames[node.ids[k]]);
      old_energy += distance_from_score(score);
    }
    if (old_energy == 0.0) return;
    Eigen::Matrix3d updated;
    const int constraint = constraints_.constraint_of[id];
    if (constraint >= 0) {
      const Eigen::Vector3d& normal = constraints_.normals[constraint];
      double sign = 1.0;
      const int axis = closest_axis(current, normal, sign);
      // Deviation: the thesis rotates the unconstrained update onto the normal; optimizing with
      // the axis held fixed gives a frame on the constraint that provably does not raise Eq. 5.6.
      updated = constrained_rotation(covariance, axis, sign * normal);
    } else {
      updated = polar_rotation(covariance);
    }
    const double new_energy = local_energy(updated, field_, node.ids, count);
    if (new_energy < old_energy) {
      // Only a visible move (above ~1e-4 rad) wakes the neighbours: the sweeps then work on the
      // part of the field that is still moving, the rest no longer affects the 0.1% criterion.
      if ((updated - current).squaredNorm() > 1e-8) changed_at_[id] = clock;
      field_.frames[id] = updated;
      // The voxel's edges are all the terms of Eq. 5.6 it changes (node.ids are its active
      // neighbours; those in other slabs do not move meanwhile), so the energy follows without a
      // pass over the field.
      decrease.add(old_energy - new_energy);
    }
  }

  FrameField& field_;
  const std::vector<Node>& nodes_;
  const ConstraintIndex& constraints_;
  const int num_slabs_;
  std::vector<std::size_t> slab_begin_;  // first node of each slab, nodes.size() at the end
  // Visit stamps: a voxel whose last update left it (nearly) unchanged and whose neighbours have
  // not moved since would get (nearly) the same result again, so it is skipped. A stamp is the
  // half-sweep number (high bits) and the step inside the slab (low bits): neighbours in other
  // slabs do not move during a half-sweep, so the comparisons never depend on the scheduling.
  std::uint64_t half_sweep_ = 0;
  std::vector<std::uint64_t> changed_at_, visited_at_;
  std::vector<Decrease> slab_decrease_;
};

// Largest angle between a constrained voxel's closest frame axis and its normal.
double max_constraint_angle(const FrameField& field, const ConstraintIndex& constraints) {
  double angle = 0.0;
  for (std::size_t i = 0; i < field.frames.size(); ++i) {
    if (constraints.constraint_of[i] < 0) continue;
    const Eigen::Vector3d& normal = constraints.normals[constraints.constraint_of[i]];
    double sign = 1.0;
    const int axis = closest_axis(field.frames[i], normal, sign);
    const double cosine = std::min(1.0, std::abs(field.frames[i].row(axis).dot(normal)));
    angle = std::max(angle, std::acos(cosine));
  }
  return angle;
}

}  // namespace

FrameSmoothingResult smooth_frame_field(const FrameField& initial, const std::vector<FrameConstraint>& constraints,
                                        const FrameSmoothingOptions& options, const Progress& progress) {
  check_smoothing_input(initial, options);
  const std::size_t n = initial.frames.size();
  const std::vector<std::uint8_t>* active = options.active.empty() ? nullptr : &options.active;
  const ConstraintIndex index = index_constraints(constraints, n, active);

  FrameSmoothingResult result;
  FrameField& field = result.field;
  field = initial;
  for (std::size_t i = 0; i < n; ++i)
    if (index.constraint_of[i] >= 0) field.frames[i] = project_to_constraint(field.frames[i], index.normals[index.constraint_of[i]]);
  const std::vector<Node> nodes = active_nodes(field, active);

  result.initial_energy = frame_smoothness_energy(field, active, options.threads);
  if (options.initialization == FrameInitialization::Propagated) propagate_from_constraints(nodes, index.constraint_of, field);
  double energy = options.initialization == FrameInitialization::Given ? result.initial_energy : frame_smoothness_energy(field, active, options.threads);
  result.start_energy = energy;
  SlabSweeper sweeper(field, nodes, index);
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    progress.report("frame smoothing", static_cast<double>(iteration - 1) / options.max_iterations);
    const double sweep_decrease = sweeper.sweep(iteration, options.threads);
    // Tracked differences carry a rounding error of ~1e-15 per update: fine against the energy of a
    // real volume, not against a field that is nearly smooth, which is summed afresh.
    double next = energy - sweep_decrease;
    if (next < 1e-2 * result.start_energy) next = frame_smoothness_energy(field, active, options.threads);
    result.energy_per_iteration.push_back(next);
    result.iterations = iteration;
    const double decrease = energy - next;
    energy = next;
    // Converged: the relative decrease criterion, or an energy at round-off level (mean edge term
    // below 1e-8, ~0.006 degrees), where relative decreases stay large while nothing visible changes.
    if (energy <= 1e-8 * static_cast<double>(nodes.size()) || decrease < options.energy_decrease_tol_rel * (energy + decrease)) {
      result.converged = true;
      break;
    }
  }
  progress.report("frame smoothing", 1.0);
  // The tracked energy differs from a fresh sum by rounding only; the result reports the fresh sum.
  energy = frame_smoothness_energy(field, active, options.threads);
  if (!result.energy_per_iteration.empty()) result.energy_per_iteration.back() = energy;
  result.final_energy = energy;
  result.max_constraint_angle_rad = max_constraint_angle(field, index);
  return result;
}

}  // namespace volspline::volume
