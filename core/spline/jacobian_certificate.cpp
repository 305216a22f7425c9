// SPDX-License-Identifier: MIT
#include "core/spline/jacobian_certificate.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/common/error.h"

namespace volspline::spline {

namespace {

constexpr double kBinomial2[3] = {1, 2, 1};
constexpr double kBinomial3[4] = {1, 3, 3, 1};
constexpr double kBinomial8[9] = {1, 8, 28, 56, 70, 56, 28, 8, 1};

inline int net(int i, int j, int k) { return i + 4 * j + 16 * k; }
inline int det_index(int i, int j, int k) { return i + 9 * j + 81 * k; }

// One box of the subdivision: det J's degree-(8,8,8) coefficients on it.
struct Box {
  double c[kJacobianCoefficients];
};

// de Casteljau at 1/2 along axis: the coefficients of the lower and upper halves.
void split_half(const double* in, int axis, double* lower, double* upper) {
  const int stride = axis == 0 ? 1 : axis == 1 ? 9 : 81;
  for (int line = 0; line < 81; ++line) {
    // line enumerates the two other indices.
    const int p = line % 9, q = line / 9;
    int base;
    if (axis == 0) base = 9 * p + 81 * q;
    else if (axis == 1) base = p + 81 * q;
    else base = p + 9 * q;
    double t[9];
    for (int i = 0; i < 9; ++i) t[i] = in[base + i * stride];
    lower[base] = t[0];
    upper[base + 8 * stride] = t[8];
    for (int r = 1; r <= 8; ++r) {
      for (int i = 0; i + r <= 8; ++i) t[i] = 0.5 * (t[i] + t[i + 1]);
      lower[base + r * stride] = t[0];
      upper[base + (8 - r) * stride] = t[8 - r];
    }
  }
}

struct Search {
  double tau = 0;
  int max_depth = 0;
  double min_coefficient = std::numeric_limits<double>::infinity();
  int leaves = 0;
  bool negative = false;
  bool undecided = false;
  double lowest_corner = std::numeric_limits<double>::infinity();
  Eigen::Vector3d lowest_corner_s = Eigen::Vector3d::Zero();
};

// The box [lo, lo + size] of the cell's local coordinates holds det J's coefficients c.
void certify_box(const double* c, int depth, const Eigen::Vector3d& lo, const Eigen::Vector3d& size, Search& search) {
  const double lowest = *std::min_element(c, c + kJacobianCoefficients);
  // The corner coefficients are det J's values at the box corners.
  for (int corner = 0; corner < 8; ++corner) {
    const double value = c[det_index(corner & 1 ? 8 : 0, corner & 2 ? 8 : 0, corner & 4 ? 8 : 0)];
    if (value < search.lowest_corner) {
      search.lowest_corner = value;
      search.lowest_corner_s = lo + Eigen::Vector3d(corner & 1, corner >> 1 & 1, corner >> 2 & 1).cwiseProduct(size);
    }
    if (value < -search.tau) search.negative = true;
  }
  if (lowest >= -search.tau || search.negative || depth >= search.max_depth) {
    search.undecided = search.undecided || (lowest < -search.tau && !search.negative);
    search.min_coefficient = std::min(search.min_coefficient, lowest);
    ++search.leaves;
    return;
  }
  Box lower, upper;
  const int axis = depth % 3;
  split_half(c, axis, lower.c, upper.c);
  Eigen::Vector3d half = size;
  half(axis) *= 0.5;
  Eigen::Vector3d upper_lo = lo;
  upper_lo(axis) += half(axis);
  certify_box(lower.c, depth + 1, lo, half, search);
  certify_box(upper.c, depth + 1, upper_lo, half, search);
}

}  // namespace

void jacobian_determinant_bernstein(const BezierCell& cell, double* coefficients, double* column_bound) {
  assert(cell.dimension == 3);
  const double* P = cell.points.data();
  // Derivative nets in the scaled Bernstein basis, structure of arrays per component:
  // du (2,3,3), dv (3,2,3), dw (3,3,2), each 48 entries.
  double du[3][3][4][4], dv[3][4][3][4], dw[3][4][4][3];
  double max_u = 0, max_v = 0, max_w = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) {
        double n2[3] = {0, 0, 0};
        for (int axis = 0; axis < 3; ++axis) {
          const int ii = i + (axis == 0), jj = j + (axis == 1), kk = k + (axis == 2);
          if (ii > 3 || jj > 3 || kk > 3) continue;
          double norm2 = 0;
          for (int d = 0; d < 3; ++d) {
            const double diff = 3.0 * (P[net(ii, jj, kk) * 3 + d] - P[net(i, j, k) * 3 + d]);
            norm2 += diff * diff;
            if (axis == 0) du[d][i][j][k] = diff * kBinomial2[i] * kBinomial3[j] * kBinomial3[k];
            if (axis == 1) dv[d][i][j][k] = diff * kBinomial3[i] * kBinomial2[j] * kBinomial3[k];
            if (axis == 2) dw[d][i][j][k] = diff * kBinomial3[i] * kBinomial3[j] * kBinomial2[k];
          }
          n2[axis] = norm2;
        }
        max_u = std::max(max_u, n2[0]);
        max_v = std::max(max_v, n2[1]);
        max_w = std::max(max_w, n2[2]);
      }
  *column_bound = std::sqrt(max_u) * std::sqrt(max_v) * std::sqrt(max_w);
  // x_v × x_w, degree (6, 5, 5), scaled basis: a convolution.
  double cross[3][7][6][6] = {};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 4; ++k) {
        const double a0 = dv[0][i][j][k], a1 = dv[1][i][j][k], a2 = dv[2][i][j][k];
        for (int I = 0; I < 4; ++I)
          for (int J = 0; J < 4; ++J)
            for (int K = 0; K < 3; ++K) {
              const double b0 = dw[0][I][J][K], b1 = dw[1][I][J][K], b2 = dw[2][I][J][K];
              cross[0][i + I][j + J][k + K] += a1 * b2 - a2 * b1;
              cross[1][i + I][j + J][k + K] += a2 * b0 - a0 * b2;
              cross[2][i + I][j + J][k + K] += a0 * b1 - a1 * b0;
            }
      }
  // x_u · (x_v × x_w), degree (8, 8, 8).
  double det[9][9][9] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) {
        const double a0 = du[0][i][j][k], a1 = du[1][i][j][k], a2 = du[2][i][j][k];
        for (int I = 0; I < 7; ++I)
          for (int J = 0; J < 6; ++J) {
            double* out = det[i + I][j + J] + k;
            const double* c0 = cross[0][I][J];
            const double* c1 = cross[1][I][J];
            const double* c2 = cross[2][I][J];
            for (int K = 0; K < 6; ++K) out[K] += a0 * c0[K] + a1 * c1[K] + a2 * c2[K];
          }
      }
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j)
      for (int k = 0; k < 9; ++k)
        coefficients[det_index(i, j, k)] = det[i][j][k] / (kBinomial8[i] * kBinomial8[j] * kBinomial8[k]);
}

JacobianCellBound certify_bezier_cell(const BezierCell& cell, const JacobianCertificateOptions& options) {
  assert(cell.dimension == 3);
  Box box;
  double column_bound = 0;
  jacobian_determinant_bernstein(cell, box.c, &column_bound);
  Search search;
  search.tau = options.rounding_rel * column_bound;
  search.max_depth = options.max_depth;
  certify_box(box.c, 0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), search);
  JacobianCellBound out;
  out.status = search.negative    ? JacobianCellStatus::Negative
               : search.undecided ? JacobianCellStatus::Undecided
                                  : JacobianCellStatus::Certified;
  const double volume = (cell.uvw_max - cell.uvw_min).prod();
  out.det_j_lower_bound = search.min_coefficient / volume;
  out.det_j_lower_bound_rel = column_bound > 0 ? search.min_coefficient / column_bound : -1.0;
  if (out.status == JacobianCellStatus::Certified) out.det_j_lower_bound_rel = std::max(0.0, out.det_j_lower_bound_rel);
  out.leaves = search.leaves;
  out.lowest_corner_s = search.lowest_corner_s;
  out.lowest_corner_rel = column_bound > 0 ? search.lowest_corner / column_bound : -1.0;
  return out;
}

JacobianCellBound JacobianCertificateCache::certify(int cuboid, const BezierCell& cell,
                                                   const JacobianCertificateOptions& options) {
  assert(cuboid >= 0 && cell.cell >= 0 && cell.dimension == 3);
  if (options.max_depth != options_.max_depth || options.rounding_rel != options_.rounding_rel) {
    entries_.clear();
    options_ = options;
  }
  if (static_cast<int>(entries_.size()) <= cuboid) entries_.resize(cuboid + 1);
  std::vector<Entry>& cells = entries_[cuboid];
  if (static_cast<int>(cells.size()) <= cell.cell) cells.resize(cell.cell + 1);
  Entry& entry = cells[cell.cell];
  // Bit for bit (memcmp: == would take −0 for +0).
  if (entry.valid && std::memcmp(entry.uvw_min.data(), cell.uvw_min.data(), 3 * sizeof(double)) == 0 &&
      std::memcmp(entry.uvw_max.data(), cell.uvw_max.data(), 3 * sizeof(double)) == 0 &&
      std::memcmp(entry.points.data(), cell.points.data(), sizeof entry.points) == 0)
    return entry.bound;
  entry.valid = true;
  std::copy(cell.points.begin(), cell.points.begin() + entry.points.size(), entry.points.begin());
  entry.uvw_min = cell.uvw_min;
  entry.uvw_max = cell.uvw_max;
  entry.bound = certify_bezier_cell(cell, options);
  return entry.bound;
}

JacobianCertificate certify_jacobian(const TSpline& spline, const JacobianCertificateOptions& options, int cuboid) {
  return certify_jacobian_in_box(spline, spline.domain_min(), spline.domain_max(), options, cuboid);
}

JacobianCertificate certify_jacobian_in_box(const TSpline& spline, const Eigen::Vector3d& box_min,
                                            const Eigen::Vector3d& box_max, const JacobianCertificateOptions& options,
                                            int cuboid, JacobianCertificateCache* cache) {
  if (spline.dimension() != 3)
    throw Error("Jacobian certificate: the spline has dimension " + std::to_string(spline.dimension()) +
                ", expected 3 (geometry)");
  if (options.max_depth < 0 || options.max_depth > 24) throw Error("Jacobian certificate: max_depth must be in [0, 24]");
  if (!(options.rounding_rel >= 0 && options.rounding_rel <= 1e-6))
    throw Error("Jacobian certificate: rounding_rel must be in [0, 1e-6]");
  JacobianCertificate out;
  for (int c = 0; c < spline.num_cells(); ++c) {
    const std::array<int, 3> k = spline.cell_index(c);
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      const double tol = 1e-9 * (box_max[a] - box_min[a]);
      inside = inside && spline.knot_lines(a)[k[a]] >= box_min[a] - tol && spline.knot_lines(a)[k[a] + 1] <= box_max[a] + tol;
    }
    if (!inside) continue;
    const BezierCell bezier = extract_bezier_cell(spline, c);
    const JacobianCellBound bound = cache ? cache->certify(cuboid, bezier, options) : certify_bezier_cell(bezier, options);
    ++out.cells;
    out.cell_bound_rel.push_back(bound.det_j_lower_bound_rel);
    out.det_j_lower_bound_rel = std::min(out.det_j_lower_bound_rel, bound.det_j_lower_bound_rel);
    if (bound.status == JacobianCellStatus::Certified) {
      ++out.certified_cells;
    } else {
      out.uncertified.push_back({cuboid, c, bezier.uvw_min, bezier.uvw_max, bound});
    }
  }
  out.jacobian_certified_fraction = out.cells ? double(out.certified_cells) / out.cells : 1.0;
  return out;
}

}  // namespace volspline::spline
