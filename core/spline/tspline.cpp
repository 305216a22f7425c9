// SPDX-License-Identifier: MIT
#include "core/spline/tspline.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <string>
#include <utility>

#include "core/common/error.h"
#include "core/spline/bspline_basis.h"
#include "core/spline/bspline_volume.h"
#include "core/spline/cell_polynomial_avx2.h"

namespace volspline::spline {

namespace {

using detail::kAxisName;
constexpr long kMaxCells = long(1) << 26;
// Smallest knot span, relative to the domain width along its axis.
constexpr double kMinSpanRel = 1e-12;
constexpr double kAutoPolynomialBytes = 256.0 * 1024 * 1024;
// Doubles after the last cell polynomial: the AVX2 Horner reads a monomial as 4 lanes.
constexpr size_t kPolynomialPad = 4;

// Tricubic power-form polynomial with K components at (s0, s1, s2) by nested Horner; c holds
// monomial m = (4 a + b) 4 + c, K values each.
template <int K>
inline void horner3(const double* coef, const double* s, double* out) {
  for (int d = 0; d < K; ++d) out[d] = 0.0;
  for (int a = 3; a >= 0; --a) {
    double acc[K] = {};
    for (int b = 3; b >= 0; --b) {
      const double* q = coef + (4 * a + b) * 4 * K;
      for (int d = 0; d < K; ++d) {
        acc[d] = acc[d] * s[1] + (((q[3 * K + d] * s[2] + q[2 * K + d]) * s[2] + q[K + d]) * s[2] + q[d]);
      }
    }
    for (int d = 0; d < K; ++d) out[d] = out[d] * s[0] + acc[d];
  }
}

// As horner3, plus the gradient with respect to (s0, s1, s2): grad[a][d].
template <int K>
inline void horner3_gradient(const double* coef, const double* s, double* out, double (*grad)[K]) {
  double t2[4][K], t2_1[4][K], t2_2[4][K];
  for (int a = 0; a < 4; ++a) {
    double t1[4][K], t1_2[4][K];
    for (int b = 0; b < 4; ++b) {
      const double* q = coef + (4 * a + b) * 4 * K;
      for (int d = 0; d < K; ++d) {
        t1[b][d] = ((q[3 * K + d] * s[2] + q[2 * K + d]) * s[2] + q[K + d]) * s[2] + q[d];
        t1_2[b][d] = (3.0 * q[3 * K + d] * s[2] + 2.0 * q[2 * K + d]) * s[2] + q[K + d];
      }
    }
    for (int d = 0; d < K; ++d) {
      t2[a][d] = ((t1[3][d] * s[1] + t1[2][d]) * s[1] + t1[1][d]) * s[1] + t1[0][d];
      t2_1[a][d] = (3.0 * t1[3][d] * s[1] + 2.0 * t1[2][d]) * s[1] + t1[1][d];
      t2_2[a][d] = ((t1_2[3][d] * s[1] + t1_2[2][d]) * s[1] + t1_2[1][d]) * s[1] + t1_2[0][d];
    }
  }
  for (int d = 0; d < K; ++d) {
    out[d] = ((t2[3][d] * s[0] + t2[2][d]) * s[0] + t2[1][d]) * s[0] + t2[0][d];
    grad[0][d] = (3.0 * t2[3][d] * s[0] + 2.0 * t2[2][d]) * s[0] + t2[1][d];
    grad[1][d] = ((t2_1[3][d] * s[0] + t2_1[2][d]) * s[0] + t2_1[1][d]) * s[0] + t2_1[0][d];
    grad[2][d] = ((t2_2[3][d] * s[0] + t2_2[2][d]) * s[0] + t2_2[1][d]) * s[0] + t2_2[0][d];
  }
}

std::uint64_t hash_knots(std::uint64_t h, const LocalKnots& r) {
  for (double k : r) {
    const double normalized = k + 0.0;  // -0.0 == 0.0
    std::uint64_t bits;
    std::memcpy(&bits, &normalized, sizeof bits);
    h = (h ^ bits) * 1099511628211ull;
    h ^= h >> 29;
  }
  return h;
}

std::string knot_text(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", t);
  return text;
}

// Kept out of line so the hot lookup stays small.
[[noreturn]] __attribute__((noinline, cold)) void throw_outside_domain(int axis, double t, double lo, double hi) {
  throw Error("T-spline: parameter " + std::string(kAxisName[axis]) + " = " + std::to_string(t) +
              " is outside the domain [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

int break_index(const std::vector<double>& breaks, double t) {
  return static_cast<int>(std::lower_bound(breaks.begin(), breaks.end(), t) - breaks.begin());
}

// Derivative of the given order of c0 + c1 s + c2 s² + c3 s³ at s, chained by inverse_width^order.
double piece_derivative(const std::array<double, 4>& c, double s, int order, double inverse_width) {
  switch (order) {
    case 0: return c[0] + s * (c[1] + s * (c[2] + s * c[3]));
    case 1: return (c[1] + s * (2.0 * c[2] + 3.0 * s * c[3])) * inverse_width;
    case 2: return (2.0 * c[2] + 6.0 * s * c[3]) * inverse_width * inverse_width;
    case 3: return 6.0 * c[3] * inverse_width * inverse_width * inverse_width;
    default: return 0.0;
  }
}

// Σ_e pu_e ⊗ pv_e ⊗ pw_e · values(f_e) over the entries e of one cell whose function f_e has
// values (a pointer to `channels` numbers, or null to skip it), in power form: sum[m·channels +
// ch], m = (4a + b)·4 + c for s0^a s1^b s2^c. A tensor-product pass as lattice_cell: the entries
// sharing a (v piece, w piece) pair are summed along u, then per w piece along v, then along w,
// so an entry costs 4 products per channel instead of 64.
struct CellSumScratch {
  std::vector<double> by_pair, by_w;
  std::vector<char> pair_used, w_used;
  std::vector<int> pairs;
};
template <int channels, class Cell, class Entry, class Values>
void cell_power_sum_impl(const Cell& cell, const Entry* entries, const std::uint32_t* ids,
                         const std::array<std::vector<std::array<double, 4>>, 3>& pieces, const Values& values,
                         CellSumScratch& w, double* sum) {
  const std::uint32_t* axis_ids[3] = {ids, ids + cell.num_pieces[0], ids + cell.num_pieces[0] + cell.num_pieces[1]};
  const int np1 = cell.num_pieces[1], np2 = cell.num_pieces[2];
  w.by_pair.resize(size_t(np1) * np2 * 4 * channels);
  w.by_w.resize(size_t(np2) * 16 * channels);
  w.pair_used.assign(size_t(np1) * np2, 0);
  w.w_used.assign(np2, 0);
  w.pairs.clear();
  for (std::uint32_t e = cell.entry_begin; e < cell.entry_end; ++e) {
    const Entry& entry = entries[e];
    const double* v = values(entry.function);
    if (!v) continue;
    const std::array<double, 4>& pu = pieces[0][axis_ids[0][entry.piece[0]]];
    const int pair = entry.piece[2] * np1 + entry.piece[1];
    double* t = w.by_pair.data() + size_t(pair) * 4 * channels;
    if (!w.pair_used[pair]) {
      w.pair_used[pair] = 1;
      w.pairs.push_back(pair);
      std::fill(t, t + 4 * channels, 0.0);
    }
    for (int a = 0; a < 4; ++a)
      for (int ch = 0; ch < channels; ++ch) t[a * channels + ch] += pu[a] * v[ch];
  }
  std::sort(w.pairs.begin(), w.pairs.end());  // a fixed order of the sums
  for (int pair : w.pairs) {
    const int pw_id = pair / np1;
    const double* t = w.by_pair.data() + size_t(pair) * 4 * channels;
    const std::array<double, 4>& pv = pieces[1][axis_ids[1][pair % np1]];
    double* t2 = w.by_w.data() + size_t(pw_id) * 16 * channels;
    if (!w.w_used[pw_id]) {
      w.w_used[pw_id] = 1;
      std::fill(t2, t2 + 16 * channels, 0.0);
    }
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        for (int ch = 0; ch < channels; ++ch) t2[(4 * a + b) * channels + ch] += t[a * channels + ch] * pv[b];
  }
  for (int pw_id = 0; pw_id < np2; ++pw_id) {
    if (!w.w_used[pw_id]) continue;
    const double* t2 = w.by_w.data() + size_t(pw_id) * 16 * channels;
    const std::array<double, 4>& pw = pieces[2][axis_ids[2][pw_id]];
    for (int ab = 0; ab < 16; ++ab)
      for (int c = 0; c < 4; ++c)
        for (int ch = 0; ch < channels; ++ch) sum[(ab * 4 + c) * channels + ch] += t2[ab * channels + ch] * pw[c];
  }
}

// cell_power_sum_impl for 1 to 5 channels (D, or D + 1 with the weights), unrolled per count.
template <class Cell, class Entry, class Values>
void cell_power_sum(const Cell& cell, const Entry* entries, const std::uint32_t* ids,
                    const std::array<std::vector<std::array<double, 4>>, 3>& pieces, int channels,
                    const Values& values, CellSumScratch& w, double* sum) {
  switch (channels) {
    case 1: return cell_power_sum_impl<1>(cell, entries, ids, pieces, values, w, sum);
    case 2: return cell_power_sum_impl<2>(cell, entries, ids, pieces, values, w, sum);
    case 3: return cell_power_sum_impl<3>(cell, entries, ids, pieces, values, w, sum);
    case 4: return cell_power_sum_impl<4>(cell, entries, ids, pieces, values, w, sum);
    default: assert(channels == 5); return cell_power_sum_impl<5>(cell, entries, ids, pieces, values, w, sum);
  }
}

// The cell polynomials of build_cell_polynomials, for the cells holding a function with
// changed[function] set (all if changed is null); each is recomputed whole, so the result is the
// same as a full build. dimension 0: the denominators alone. Cell and Entry are TSpline's
// (deduced: private types).
template <class Cell, class Entry>
void fill_cell_polynomials(const std::vector<Cell>& cells, const std::vector<Entry>& entries,
                           const std::vector<std::uint32_t>& cell_pieces,
                           const std::array<std::vector<std::array<double, 4>>, 3>& pieces,
                           const std::vector<double>& weighted_points, const Eigen::VectorXd& weights,
                           int dimension, const std::vector<char>* changed, std::vector<double>& cell_numerator,
                           std::vector<double>& cell_denominator) {
  // (w p, w) per function: the numerator's and the denominator's channels in one pass.
  const int channels = dimension + 1;
  std::vector<double> values(size_t(weights.size()) * channels);
  for (Eigen::Index f = 0; f < weights.size(); ++f) {
    for (int d = 0; d < dimension; ++d) values[size_t(f) * channels + d] = weighted_points[size_t(f) * dimension + d];
    values[size_t(f) * channels + dimension] = weights[f];
  }
  auto value_of = [&](std::uint32_t f) { return values.data() + size_t(f) * channels; };
  CellSumScratch scratch;
  double sum[64 * 5];
  for (size_t c = 0; c < cells.size(); ++c) {
    const Cell& cell = cells[c];
    if (changed) {
      bool any = false;
      for (std::uint32_t e = cell.entry_begin; e < cell.entry_end && !any; ++e) any = (*changed)[entries[e].function];
      if (!any) continue;
    }
    std::fill(sum, sum + 64 * channels, 0.0);
    cell_power_sum(cell, entries.data(), cell_pieces.data() + cell.piece_begin, pieces, channels, value_of, scratch,
                   sum);
    double* numerator = cell_numerator.data() + c * 64 * dimension;
    double* denominator = cell_denominator.data() + c * 64;
    for (int m = 0; m < 64; ++m) {
      for (int d = 0; d < dimension; ++d) numerator[m * dimension + d] = sum[m * channels + d];
      denominator[m] = sum[m * channels + dimension];
    }
  }
}

// Adds Σ B_i·delta_i over the functions with changed[i] set to the cell numerators: the update of
// fill_cell_polynomials for a few moved control points (delta: the change of w_i·p_i, n×D),
// at a cost of the moved functions' entries only. Agrees with a full build to rounding.
template <class Cell, class Entry>
void add_cell_polynomial_changes(const std::vector<Cell>& cells, const std::vector<Entry>& entries,
                                 const std::vector<std::uint32_t>& cell_pieces,
                                 const std::array<std::vector<std::array<double, 4>>, 3>& pieces,
                                 const std::vector<double>& delta, int dimension, const std::vector<char>& changed,
                                 std::vector<double>& cell_numerator) {
  auto delta_of = [&](std::uint32_t f) { return changed[f] ? delta.data() + size_t(f) * dimension : nullptr; };
  CellSumScratch scratch;
  for (size_t c = 0; c < cells.size(); ++c) {
    const Cell& cell = cells[c];
    bool any = false;
    for (std::uint32_t e = cell.entry_begin; e < cell.entry_end && !any; ++e) any = changed[entries[e].function];
    if (!any) continue;
    cell_power_sum(cell, entries.data(), cell_pieces.data() + cell.piece_begin, pieces, dimension, delta_of, scratch,
                   cell_numerator.data() + c * 64 * dimension);
  }
}

// Tensor-product pass of TSpline::evaluate_lattice_with_jacobian over the lattice points of one
// cell (n[a] of them along axis a, local coordinates s[a][0..n[a])): stage 1 sums the functions
// sharing a (v piece, w piece) pair along u, stage 2 those sharing a w piece along v, stage 3
// along w. out: per point (k, j, i) the value and the three s-derivatives, D values each.
// Cell and Entry are TSpline's (deduced: private types).
struct LatticeScratch {
  std::vector<double> piece_values[3];  // [piece][point][value, s-derivative]
  std::vector<double> by_pair, by_w, out;
  std::vector<int> pair_stamp, w_stamp, pairs, ws;
  int stamp = 0;
};
// lattice_cell from the cell's tricubic power form (coef: 64·D, index ((4a + b)·4 + c)·D + d for
// s0^a s1^b s2^c): the same tensor-product pass over 64 coefficients instead of the cell's
// blending functions (bunny: up to 145 per cell), w first as the coefficients are laid out.
template <int D>
void lattice_cell_polynomial(const double* coef, const int* n, const double* const* s, LatticeScratch& w) {
  const int nu = n[0], nv = n[1], nw = n[2];
  // Powers and their derivatives per axis and point: [point][value 0..3, derivative 0..3].
  for (int a = 0; a < 3; ++a) {
    std::vector<double>& p = w.piece_values[a];
    p.resize(size_t(n[a]) * 8);
    for (int i = 0; i < n[a]; ++i) {
      const double t = s[a][i];
      double* q = p.data() + size_t(i) * 8;
      q[0] = 1.0, q[1] = t, q[2] = t * t, q[3] = t * t * t;
      q[4] = 0.0, q[5] = 1.0, q[6] = 2.0 * t, q[7] = 3.0 * t * t;
    }
  }
  const double* pu = w.piece_values[0].data();
  const double* pv = w.piece_values[1].data();
  const double* pw = w.piece_values[2].data();
  // t1[(ab)·nw + k][value, ∂w][d] = Σ_c coef[ab c] pw_k[c].
  w.by_pair.resize(size_t(16) * nw * 2 * D);
  double* t1 = w.by_pair.data();
  for (int ab = 0; ab < 16; ++ab)
    for (int k = 0; k < nw; ++k) {
      const double* q = coef + size_t(ab) * 4 * D;
      const double* b = pw + size_t(k) * 8;
      double* o = t1 + (size_t(ab) * nw + k) * 2 * D;
      for (int d = 0; d < D; ++d) {
        o[d] = q[d] * b[0] + q[D + d] * b[1] + q[2 * D + d] * b[2] + q[3 * D + d] * b[3];
        o[D + d] = q[D + d] * b[5] + q[2 * D + d] * b[6] + q[3 * D + d] * b[7];
      }
    }
  // t2[(a·nv + j)·nw + k][value, ∂v, ∂w][d] = Σ_b t1[ab k] pv_j[b].
  w.by_w.resize(size_t(4) * nv * nw * 3 * D);
  double* t2 = w.by_w.data();
  for (int a = 0; a < 4; ++a)
    for (int j = 0; j < nv; ++j) {
      const double* b = pv + size_t(j) * 8;
      for (int k = 0; k < nw; ++k) {
        double* o = t2 + ((size_t(a) * nv + j) * nw + k) * 3 * D;
        const double* q0 = t1 + (size_t(4 * a + 0) * nw + k) * 2 * D;
        const double* q1 = t1 + (size_t(4 * a + 1) * nw + k) * 2 * D;
        const double* q2 = t1 + (size_t(4 * a + 2) * nw + k) * 2 * D;
        const double* q3 = t1 + (size_t(4 * a + 3) * nw + k) * 2 * D;
        for (int d = 0; d < D; ++d) {
          o[d] = q0[d] * b[0] + q1[d] * b[1] + q2[d] * b[2] + q3[d] * b[3];
          o[D + d] = q1[d] * b[5] + q2[d] * b[6] + q3[d] * b[7];
          o[2 * D + d] = q0[D + d] * b[0] + q1[D + d] * b[1] + q2[D + d] * b[2] + q3[D + d] * b[3];
        }
      }
    }
  // out[(k·nv + j)·nu + i][value, ∂u, ∂v, ∂w][d] = Σ_a t2[a j k] pu_i[a].
  w.out.resize(size_t(nu) * nv * nw * 4 * D);
  for (int k = 0; k < nw; ++k)
    for (int j = 0; j < nv; ++j) {
      const double* q0 = t2 + ((size_t(0) * nv + j) * nw + k) * 3 * D;
      const double* q1 = t2 + ((size_t(1) * nv + j) * nw + k) * 3 * D;
      const double* q2 = t2 + ((size_t(2) * nv + j) * nw + k) * 3 * D;
      const double* q3 = t2 + ((size_t(3) * nv + j) * nw + k) * 3 * D;
      for (int i = 0; i < nu; ++i) {
        const double* b = pu + size_t(i) * 8;
        double* o = w.out.data() + ((size_t(k) * nv + j) * nu + i) * 4 * D;
        for (int d = 0; d < D; ++d) {
          o[d] = q0[d] * b[0] + q1[d] * b[1] + q2[d] * b[2] + q3[d] * b[3];
          o[D + d] = q1[d] * b[5] + q2[d] * b[6] + q3[d] * b[7];
          o[2 * D + d] = q0[D + d] * b[0] + q1[D + d] * b[1] + q2[D + d] * b[2] + q3[D + d] * b[3];
          o[3 * D + d] = q0[2 * D + d] * b[0] + q1[2 * D + d] * b[1] + q2[2 * D + d] * b[2] + q3[2 * D + d] * b[3];
        }
      }
    }
}

template <int D, class Cell, class Entry>
void lattice_cell(const Cell& cell, const Entry* entries, const std::uint32_t* ids,
                  const std::array<std::vector<std::array<double, 4>>, 3>& pieces, const double* weighted_points,
                  const int* n, const double* const* s, LatticeScratch& w) {
  const int np[3] = {cell.num_pieces[0], cell.num_pieces[1], cell.num_pieces[2]};
  for (int a = 0, offset = 0; a < 3; ++a) {
    std::vector<double>& values = w.piece_values[a];
    values.resize(size_t(np[a]) * n[a] * 2);
    for (int p = 0; p < np[a]; ++p) {
      const std::array<double, 4>& c = pieces[a][ids[offset + p]];
      for (int i = 0; i < n[a]; ++i) {
        const double t = s[a][i];
        values[(size_t(p) * n[a] + i) * 2] = c[0] + t * (c[1] + t * (c[2] + t * c[3]));
        values[(size_t(p) * n[a] + i) * 2 + 1] = c[1] + t * (2.0 * c[2] + 3.0 * t * c[3]);
      }
    }
    offset += np[a];
  }
  const int nu = n[0], nv = n[1], nw = n[2];
  const size_t pair_size = size_t(nu) * 2 * D, w_size = size_t(nv) * nu * 3 * D;
  const size_t num_pairs = size_t(np[1]) * np[2];
  if (w.pair_stamp.size() < num_pairs) w.pair_stamp.resize(num_pairs, -1);
  if (w.w_stamp.size() < size_t(np[2])) w.w_stamp.resize(np[2], -1);
  if (w.by_pair.size() < num_pairs * pair_size) w.by_pair.resize(num_pairs * pair_size);
  if (w.by_w.size() < np[2] * w_size) w.by_w.resize(np[2] * w_size);
  ++w.stamp;
  w.pairs.clear();
  w.ws.clear();
  const double* u_values = w.piece_values[0].data();
  for (std::uint32_t e = cell.entry_begin; e < cell.entry_end; ++e) {
    const Entry& entry = entries[e];
    const int pair = entry.piece[2] * np[1] + entry.piece[1];
    double* t = w.by_pair.data() + pair * pair_size;
    if (w.pair_stamp[pair] != w.stamp) {
      w.pair_stamp[pair] = w.stamp;
      w.pairs.push_back(pair);
      std::fill(t, t + pair_size, 0.0);
    }
    const double* wp = weighted_points + size_t(entry.function) * D;
    const double* bu = u_values + size_t(entry.piece[0]) * nu * 2;
    for (int i = 0; i < nu; ++i)
      for (int d = 0; d < D; ++d) {
        t[(2 * i) * D + d] += bu[2 * i] * wp[d];
        t[(2 * i + 1) * D + d] += bu[2 * i + 1] * wp[d];
      }
  }
  const double* v_values = w.piece_values[1].data();
  for (int pair : w.pairs) {
    const int pv = pair % np[1], pw = pair / np[1];
    double* t2 = w.by_w.data() + pw * w_size;
    if (w.w_stamp[pw] != w.stamp) {
      w.w_stamp[pw] = w.stamp;
      w.ws.push_back(pw);
      std::fill(t2, t2 + w_size, 0.0);
    }
    const double* t1 = w.by_pair.data() + pair * pair_size;
    const double* bv = v_values + size_t(pv) * nv * 2;
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        double* o = t2 + (size_t(j) * nu + i) * 3 * D;
        const double* in = t1 + size_t(i) * 2 * D;
        for (int d = 0; d < D; ++d) {
          o[d] += in[d] * bv[2 * j];
          o[D + d] += in[D + d] * bv[2 * j];
          o[2 * D + d] += in[d] * bv[2 * j + 1];
        }
      }
  }
  const double* w_values = w.piece_values[2].data();
  const size_t points = size_t(nu) * nv * nw;
  w.out.assign(points * 4 * D, 0.0);
  for (int pw : w.ws) {
    const double* t2 = w.by_w.data() + pw * w_size;
    const double* bw = w_values + size_t(pw) * nw * 2;
    for (int k = 0; k < nw; ++k)
      for (int ji = 0; ji < nv * nu; ++ji) {
        double* o = w.out.data() + (size_t(k) * nv * nu + ji) * 4 * D;
        const double* in = t2 + size_t(ji) * 3 * D;
        for (int d = 0; d < D; ++d) {
          o[d] += in[d] * bw[2 * k];
          o[D + d] += in[D + d] * bw[2 * k];
          o[2 * D + d] += in[2 * D + d] * bw[2 * k];
          o[3 * D + d] += in[d] * bw[2 * k + 1];
        }
      }
  }
}

}  // namespace

std::size_t KnotsHash::operator()(const LocalKnots& knots) const {
  return static_cast<std::size_t>(hash_knots(1469598103934665603ull, knots));
}

std::size_t KnotsHash::operator()(const BlendingKnots& knots) const {
  std::uint64_t h = 1469598103934665603ull;
  for (const LocalKnots& r : knots) h = hash_knots(h, r);
  return static_cast<std::size_t>(h);
}

TSpline::TSpline(std::vector<BlendingKnots> knots, Eigen::VectorXd weights, Eigen::MatrixXd points,
                 TSplineAcceleration acceleration)
    : knots_(std::move(knots)), weights_(std::move(weights)), points_(std::move(points)) {
#if defined(VOLSPLINE_AVX2_KERNELS)
  avx2_ = __builtin_cpu_supports("avx2");
#endif
  const Eigen::Index n = static_cast<Eigen::Index>(knots_.size());
  if (n == 0) throw Error("T-spline: no blending functions");
  if (weights_.size() != n) {
    throw Error("T-spline: " + std::to_string(weights_.size()) + " weights for " + std::to_string(n) +
                " blending functions");
  }
  if (points_.rows() != n) {
    throw Error("T-spline: " + std::to_string(points_.rows()) + " control points for " +
                std::to_string(n) + " blending functions");
  }
  if (points_.cols() < 1 || points_.cols() > 4) {
    throw Error("T-spline: control point dimension " + std::to_string(points_.cols()) + " is not in 1..4");
  }
  if (n > std::numeric_limits<std::int32_t>::max()) throw Error("T-spline: too many blending functions");
  dimension_ = static_cast<int>(points_.cols());
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (!local_knots_valid(knots_[i][a])) {
        throw Error("T-spline: blending function " + std::to_string(i) + ": knot vector " + kAxisName[a] +
                    " is not finite and non-decreasing with r0 < r4");
      }
    }
    if (!(std::isfinite(weights_[i]) && weights_[i] > 0.0)) {
      throw Error("T-spline: blending function " + std::to_string(i) + ": weight " +
                  std::to_string(weights_[i]) + " is not finite and positive");
    }
  }
  set_points(points_);
  build_grid();
  if (acceleration == TSplineAcceleration::CellPolynomials) build_cell_polynomials();
  if (acceleration == TSplineAcceleration::Auto) use_cell_polynomials();
}

bool TSpline::use_cell_polynomials() {
  const double polynomial_bytes = double(cells_.size()) * 64 * (dimension_ + 1) * sizeof(double);
  if (!has_cell_polynomials() && polynomial_bytes <= kAutoPolynomialBytes) build_cell_polynomials();
  return has_cell_polynomials();
}

// F and Σ w B restricted to one cell are sums of tensor products of the power-form pieces.
void TSpline::build_cell_polynomials() {
  cell_numerator_.assign(cells_.size() * 64 * dimension_ + kPolynomialPad, 0.0);
  cell_denominator_.assign(cells_.size() * 64 + kPolynomialPad, 0.0);
  // A spline built before its control points are known (all zero, as GpcSpline's patches) has a
  // zero numerator: Σ w_i B_i is summed alone (its channel's sums do not depend on the others).
  const bool zero = std::all_of(weighted_points_.begin(), weighted_points_.end(), [](double x) { return x == 0.0; });
  fill_cell_polynomials(cells_, entries_, cell_pieces_, pieces_, weighted_points_, weights_, zero ? 0 : dimension_,
                        nullptr, cell_numerator_, cell_denominator_);
}

std::array<int, 3> TSpline::cell_index(int cell) const {
  assert(cell >= 0 && cell < num_cells());
  const int n0 = int(breaks_[0].size() - 1), n1 = int(breaks_[1].size() - 1);
  return {cell % n0, (cell / n0) % n1, cell / (n0 * n1)};
}

void TSpline::cell_power_form(int cell, double* numerator, double* denominator) const {
  assert(cell >= 0 && cell < num_cells());
  const int dim = dimension_;
  if (has_cell_polynomials()) {
    std::copy_n(cell_numerator_.data() + size_t(cell) * 64 * dim, 64 * dim, numerator);
    std::copy_n(cell_denominator_.data() + size_t(cell) * 64, 64, denominator);
    return;
  }
  const Cell& c = cells_[cell];
  const std::uint32_t* ids = cell_pieces_.data() + c.piece_begin;
  CellSumScratch scratch;
  std::fill_n(numerator, 64 * dim, 0.0);
  std::fill_n(denominator, 64, 0.0);
  cell_power_sum(c, entries_.data(), ids, pieces_, dim,
                 [&](std::uint32_t f) { return weighted_points_.data() + size_t(f) * dim; }, scratch, numerator);
  cell_power_sum(c, entries_.data(), ids, pieces_, 1, [&](std::uint32_t f) { return weights_.data() + f; }, scratch,
                 denominator);
}

void TSpline::set_points(Eigen::MatrixXd points) {
  if (points.rows() != num_functions() || points.cols() != dimension_) {
    throw Error("T-spline: new control points are " + std::to_string(points.rows()) + "x" +
                std::to_string(points.cols()) + ", expected " + std::to_string(num_functions()) + "x" +
                std::to_string(dimension_));
  }
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    if (!points.row(i).allFinite()) {
      throw Error("T-spline: control point " + std::to_string(i) + " is not finite");
    }
  }
  // Only the cells of functions whose control point changed need new polynomials (the
  // untangling moves a few interior points of a large spline).
  std::vector<char> changed;
  Eigen::Index num_changed = 0;
  if (!cell_numerator_.empty()) {
    changed.resize(size_t(points.rows()));
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      changed[size_t(i)] = points.row(i) != points_.row(i);
      num_changed += changed[size_t(i)];
    }
  }
  // At most half the points moved (the untangling moves a few interior ones): add their change
  // to the cell numerators (Σ w_i B_i does not change); else rebuild the touched cells whole.
  const bool incremental = !cell_numerator_.empty() && 2 * num_changed <= points.rows();
  std::vector<double> delta;
  if (incremental) {
    delta.assign(size_t(points.rows()) * dimension_, 0.0);
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      if (!changed[size_t(i)]) continue;
      for (int d = 0; d < dimension_; ++d)
        delta[size_t(i) * dimension_ + d] = weights_[i] * points(i, d) - weighted_points_[size_t(i) * dimension_ + d];
    }
  }
  points_ = std::move(points);
  weighted_points_.resize(size_t(points_.rows()) * dimension_);
  for (Eigen::Index i = 0; i < points_.rows(); ++i) {
    for (int d = 0; d < dimension_; ++d) weighted_points_[size_t(i) * dimension_ + d] = weights_[i] * points_(i, d);
  }
  if (incremental) {
    add_cell_polynomial_changes(cells_, entries_, cell_pieces_, pieces_, delta, dimension_, changed, cell_numerator_);
  } else if (!cell_numerator_.empty()) {
    fill_cell_polynomials(cells_, entries_, cell_pieces_, pieces_, weighted_points_, weights_, dimension_, &changed,
                          cell_numerator_, cell_denominator_);
  }
}

void TSpline::build_grid() {
  build_breaks();
  std::array<std::vector<int>, 3> first_cell;   // per function: first grid interval of support
  std::array<std::vector<int>, 3> first_piece;  // per function: piece id of that interval
  build_pieces(first_cell, first_piece);
  const std::vector<std::uint64_t> counts = build_cell_entries(first_cell);
  build_cell_pieces(first_cell, first_piece, counts);
}

void TSpline::build_breaks() {
  long num_cells = 1;
  for (int a = 0; a < 3; ++a) {
    std::vector<double>& b = breaks_[a];
    b.clear();
    for (const BlendingKnots& k : knots_) b.insert(b.end(), k[a].begin(), k[a].end());
    std::sort(b.begin(), b.end());
    b.erase(std::unique(b.begin(), b.end()), b.end());
    // Knot spans far below the domain (or a domain below the resolution of its coordinates) make
    // the lookup scale overflow and the local coordinates meaningless: refuse them.
    const double extent = b.back() - b.front();
    const double magnitude = std::max(std::abs(b.front()), std::abs(b.back()));
    if (!(std::isfinite(extent) && extent > 0.0 && extent >= kMinSpanRel * magnitude &&
          std::isfinite(double(std::min(4 * int(b.size() - 1) + 1, 1 << 20)) / extent))) {
      throw Error(std::string("T-spline: the ") + kAxisName[a] + " knots span [" + knot_text(b.front()) + ", " +
                  knot_text(b.back()) + "], not a usable domain (finite, wider than 1e-12 of its coordinates)");
    }
    for (size_t k = 0; k + 1 < b.size(); ++k) {
      if (b[k + 1] - b[k] < kMinSpanRel * extent) {
        throw Error(std::string("T-spline: a ") + kAxisName[a] + " knot span [" + knot_text(b[k]) + ", " +
                    knot_text(b[k + 1]) + "] is below 1e-12 of the domain width");
      }
    }
    inverse_widths_[a].resize(b.size() - 1);
    for (size_t k = 0; k + 1 < b.size(); ++k) inverse_widths_[a][k] = 1.0 / (b[k + 1] - b[k]);
    // Uniform bins over the axis, each holding the grid interval of its start, so locate()
    // needs a table lookup and a step or two instead of a binary search.
    const int m = int(b.size() - 1);
    const int num_bins = std::min(4 * m + 1, 1 << 20);
    bin_scale_[a] = num_bins / (b.back() - b.front());
    bin_first_[a].resize(num_bins);
    for (int bin = 0; bin < num_bins; ++bin) {
      const double x = b.front() + bin / bin_scale_[a];
      bin_first_[a][bin] = std::min(m - 1, static_cast<int>(std::upper_bound(b.begin(), b.end(), x) - b.begin()) - 1);
    }
    num_cells *= long(m);
    if (num_cells > kMaxCells) {
      throw Error("T-spline: the knot-line grid has more than " + std::to_string(kMaxCells) + " cells");
    }
  }
}

void TSpline::build_pieces(std::array<std::vector<int>, 3>& first_cell, std::array<std::vector<int>, 3>& first_piece) {
  const int n = num_functions();
  // Pieces: one power-form cubic per (univariate knot vector, grid interval), shared by all
  // blending functions with that knot vector. Coefficients are the Taylor expansion at the
  // interval start in s = (t - b_k) / (b_{k+1} - b_k).
  for (int a = 0; a < 3; ++a) {
    // Knot vector -> its first piece (the first grid interval follows from r0).
    std::unordered_map<LocalKnots, int, KnotsHash> piece_ids;
    pieces_[a].clear();
    first_cell[a].resize(n);
    first_piece[a].resize(n);
    for (int i = 0; i < n; ++i) {
      const LocalKnots& r = knots_[i][a];
      const int k0 = break_index(breaks_[a], r[0]);
      const int k1 = break_index(breaks_[a], r[4]);
      first_cell[a][i] = k0;
      const auto found = piece_ids.find(r);
      if (found != piece_ids.end()) {
        first_piece[a][i] = found->second;
        continue;
      }
      first_piece[a][i] = static_cast<int>(pieces_[a].size());
      piece_ids.emplace(r, first_piece[a][i]);
      for (int k = k0; k < k1; ++k) {
        const double start = breaks_[a][k];
        const double h = breaks_[a][k + 1] - start;
        const BasisDerivatives d = cubic_basis_piece_derivatives(r, cubic_basis_interval(r, start, RightEnd::Open), start);
        pieces_[a].push_back({d.value, d.d1 * h, d.d2 * h * h / 2.0, d.d3 * h * h * h / 6.0});
      }
    }
  }
}

std::vector<std::uint64_t> TSpline::build_cell_entries(const std::array<std::vector<int>, 3>& first_cell) {
  const int n = num_functions();
  const int nc[3] = {int(breaks_[0].size() - 1), int(breaks_[1].size() - 1), int(breaks_[2].size() - 1)};
  // Cells in CSR form: count, then fill in function order (so entries are sorted by function).
  cells_.assign(size_t(nc[0]) * nc[1] * nc[2], Cell{});
  std::array<std::array<int, 2>, 3> range;
  auto support_range = [&](int i) {
    for (int a = 0; a < 3; ++a) {
      range[a] = {first_cell[a][i], break_index(breaks_[a], knots_[i][a][4])};
    }
  };
  std::vector<std::uint64_t> counts(cells_.size() + 1, 0);
  for (int i = 0; i < n; ++i) {
    support_range(i);
    for (int k2 = range[2][0]; k2 < range[2][1]; ++k2)
      for (int k1 = range[1][0]; k1 < range[1][1]; ++k1)
        for (int k0 = range[0][0]; k0 < range[0][1]; ++k0) ++counts[size_t(k0) + nc[0] * (size_t(k1) + nc[1] * size_t(k2)) + 1];
  }
  for (size_t c = 0; c < cells_.size(); ++c) counts[c + 1] += counts[c];
  if (counts.back() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("T-spline: too many (cell, blending function) overlaps for the acceleration grid");
  }
  entries_.assign(counts.back(), Entry{});
  std::vector<std::uint64_t> fill(counts.begin(), counts.end() - 1);
  for (int i = 0; i < n; ++i) {
    support_range(i);
    for (int k2 = range[2][0]; k2 < range[2][1]; ++k2)
      for (int k1 = range[1][0]; k1 < range[1][1]; ++k1)
        for (int k0 = range[0][0]; k0 < range[0][1]; ++k0) {
          const size_t c = size_t(k0) + nc[0] * (size_t(k1) + nc[1] * size_t(k2));
          const size_t e = fill[c]++;
          entries_[e].function = static_cast<std::uint32_t>(i);
        }
  }
  return counts;
}

void TSpline::build_cell_pieces(const std::array<std::vector<int>, 3>& first_cell,
                                const std::array<std::vector<int>, 3>& first_piece,
                                const std::vector<std::uint64_t>& counts) {
  const int nc[3] = {int(breaks_[0].size() - 1), int(breaks_[1].size() - 1), int(breaks_[2].size() - 1)};
  // Per cell: the distinct pieces per axis (first-appearance order) and local indices.
  cell_pieces_.clear();
  max_functions_per_cell_ = 0;
  std::vector<std::uint32_t> distinct;
  // Local index of each piece in the current (cell, axis), valid where its stamp matches.
  std::array<std::vector<std::uint32_t>, 3> local_of, stamp;
  for (int a = 0; a < 3; ++a) {
    local_of[a].assign(pieces_[a].size(), 0);
    stamp[a].assign(pieces_[a].size(), std::numeric_limits<std::uint32_t>::max());
  }
  // The piece of function i in grid interval k along axis a is first_piece + k − first_cell
  // (computed here instead of stored per entry, which would double the grid's peak memory).
  for (size_t c = 0; c < cells_.size(); ++c) {
    Cell& cell = cells_[c];
    const int cell_k[3] = {int(c % size_t(nc[0])), int((c / size_t(nc[0])) % size_t(nc[1])),
                           int(c / (size_t(nc[0]) * nc[1]))};
    cell.entry_begin = static_cast<std::uint32_t>(counts[c]);
    cell.entry_end = static_cast<std::uint32_t>(counts[c + 1]);
    cell.piece_begin = static_cast<std::uint32_t>(cell_pieces_.size());
    max_functions_per_cell_ = std::max(max_functions_per_cell_, int(cell.entry_end - cell.entry_begin));
    for (int a = 0; a < 3; ++a) {
      distinct.clear();
      for (std::uint32_t e = cell.entry_begin; e < cell.entry_end; ++e) {
        const std::uint32_t i = entries_[e].function;
        const std::uint32_t p = std::uint32_t(first_piece[a][i] + cell_k[a] - first_cell[a][i]);
        if (stamp[a][p] != std::uint32_t(c)) {
          if (distinct.size() == std::numeric_limits<std::uint16_t>::max()) {
            throw Error("T-spline: more than 65535 distinct knot vectors overlap one cell");
          }
          stamp[a][p] = std::uint32_t(c);
          local_of[a][p] = static_cast<std::uint32_t>(distinct.size());
          distinct.push_back(p);
        }
        entries_[e].piece[a] = static_cast<std::uint16_t>(local_of[a][p]);
      }
      cell.num_pieces[a] = static_cast<std::uint16_t>(distinct.size());
      cell_pieces_.insert(cell_pieces_.end(), distinct.begin(), distinct.end());
    }
    if (cell_pieces_.size() > std::numeric_limits<std::uint32_t>::max()) {
      throw Error("T-spline: acceleration grid too large");
    }
  }
}

// Cell index of uvw; k[a] = grid interval and local[a] = position in it in [0, 1] along axis a.
__attribute__((always_inline)) inline int TSpline::locate(const Eigen::Vector3d& uvw, double* local, int* k) const {
  for (int a = 0; a < 3; ++a) {
    const std::vector<double>& b = breaks_[a];
    const double t = uvw[a];
    if (!(t >= b.front() && t <= b.back())) throw_outside_domain(a, t, b.front(), b.back());
    // The last cell is closed at the domain end.
    const int m = int(b.size() - 1);
    const std::vector<int>& bins = bin_first_[a];
    int j = bins[std::min(static_cast<int>((t - b.front()) * bin_scale_[a]), int(bins.size()) - 1)];
    while (j + 1 < m && b[j + 1] <= t) ++j;
    while (j > 0 && b[j] > t) --j;
    k[a] = j;
    local[a] = (t - b[k[a]]) * inverse_widths_[a][k[a]];
  }
  return k[0] + int(breaks_[0].size() - 1) * (k[1] + int(breaks_[1].size() - 1) * k[2]);
}

// Eq. 4.3 (semi-standard) or Eq. 4.1 (kRational); jacobian by the product rule, and for the
// rational form the quotient rule (N' - F W') / W.
template <int D, bool kRational, bool kJacobian>
void TSpline::evaluate_impl(const Eigen::Vector3d& uvw, double* value, double* jacobian) const {
  double s[3];
  int k[3];
  const int cell = locate(uvw, s, k);
  evaluate_at<D, kRational, kJacobian>(cell, s, k, value, jacobian);
}

template <int D, bool kRational, bool kJacobian>
inline void TSpline::evaluate_at(int cell_index, const double* s, const int* k, double* value, double* jacobian) const {
  if (!cell_numerator_.empty()) {
    evaluate_polynomial<D, kRational, kJacobian>(cell_index, s, k, value, jacobian);
    return;
  }
  const Cell& cell = cells_[cell_index];
  const int total = cell.num_pieces[0] + cell.num_pieces[1] + cell.num_pieces[2];
  constexpr int kStack = 96;
  double stack_values[2 * kStack];
  std::vector<double> heap_values;
  double* basis = stack_values;
  if (total > kStack) {
    heap_values.resize(2 * size_t(total));
    basis = heap_values.data();
  }
  double* axis_values[3];
  double* axis_derivs[3];
  const std::uint32_t* ids = cell_pieces_.data() + cell.piece_begin;
  int offset = 0;
  for (int a = 0; a < 3; ++a) {
    axis_values[a] = basis + offset;
    axis_derivs[a] = basis + total + offset;
    const double t = s[a];
    for (int m = 0; m < cell.num_pieces[a]; ++m) {
      const std::array<double, 4>& c = pieces_[a][ids[offset + m]];
      axis_values[a][m] = c[0] + t * (c[1] + t * (c[2] + t * c[3]));
      if (kJacobian) axis_derivs[a][m] = c[1] + t * (2.0 * c[2] + 3.0 * t * c[3]);
    }
    offset += cell.num_pieces[a];
  }

  double sum[D] = {};
  double sum_d[3][D] = {};
  double weight = 0.0;
  double weight_d[3] = {0.0, 0.0, 0.0};
  const Entry* entries = entries_.data();
  const double* wp_all = weighted_points_.data();
  const double* w_all = weights_.data();
  for (std::uint32_t e = cell.entry_begin; e < cell.entry_end; ++e) {
    const Entry& entry = entries[e];
    const double bu = axis_values[0][entry.piece[0]];
    const double bv = axis_values[1][entry.piece[1]];
    const double bw = axis_values[2][entry.piece[2]];
    const double bvw = bv * bw;
    const double b = bu * bvw;
    const double* wp = wp_all + size_t(entry.function) * D;
    for (int d = 0; d < D; ++d) sum[d] += b * wp[d];
    if (kRational) weight += b * w_all[entry.function];
    if (kJacobian) {
      const double grad[3] = {axis_derivs[0][entry.piece[0]] * bvw,
                              bu * axis_derivs[1][entry.piece[1]] * bw,
                              bu * bv * axis_derivs[2][entry.piece[2]]};
      for (int a = 0; a < 3; ++a) {
        for (int d = 0; d < D; ++d) sum_d[a][d] += grad[a] * wp[d];
        if (kRational) weight_d[a] += grad[a] * w_all[entry.function];
      }
    }
  }

  if (kRational) {
    const double inverse_weight = 1.0 / weight;
    for (int d = 0; d < D; ++d) value[d] = sum[d] * inverse_weight;
  } else {
    for (int d = 0; d < D; ++d) value[d] = sum[d];
  }
  if (kJacobian) {
    for (int a = 0; a < 3; ++a) {
      const double inverse_width = inverse_widths_[a][k[a]];
      for (int d = 0; d < D; ++d) {
        double g = sum_d[a][d] * inverse_width;
        if (kRational) g = (g - value[d] * weight_d[a] * inverse_width) / weight;
        jacobian[d + D * a] = g;
      }
    }
  }
}

template <int D, bool kRational, bool kJacobian>
void TSpline::evaluate_polynomial(int cell, const double* s, const int* k, double* value, double* jacobian) const {
  const double* numerator = cell_numerator_.data() + size_t(cell) * 64 * D;
  const double* denominator = cell_denominator_.data() + size_t(cell) * 64;
#if defined(VOLSPLINE_AVX2_KERNELS)
  // The denominator rides in the lane after the D components; D = 4 leaves none free.
  constexpr bool kSharedLane = kRational && D < 4;
#endif
  if (!kJacobian) {
    double weight = 1.0;
#if defined(VOLSPLINE_AVX2_KERNELS)
    if (avx2_) {
      double lanes[4];
      detail::cell_horner_avx2<D, kSharedLane>(numerator, denominator, s, lanes);
      for (int d = 0; d < D; ++d) value[d] = lanes[d];
      if constexpr (kSharedLane) {
        weight = lanes[D];
      } else if constexpr (kRational) {
        detail::cell_horner_avx2<1, false>(denominator, nullptr, s, lanes);
        weight = lanes[0];
      }
    } else
#endif
    {
      horner3<D>(numerator, s, value);
      if (kRational) horner3<1>(denominator, s, &weight);
    }
    if (kRational) {
      const double inverse_weight = 1.0 / weight;
      for (int d = 0; d < D; ++d) value[d] *= inverse_weight;
    }
    return;
  }
  double grad[3][D];
  double weight = 1.0, weight_grad[3][1] = {{0.0}, {0.0}, {0.0}};
#if defined(VOLSPLINE_AVX2_KERNELS)
  if (avx2_) {
    double lanes[16];
    detail::cell_horner_gradient_avx2<D, kSharedLane>(numerator, denominator, s, lanes);
    for (int d = 0; d < D; ++d) {
      value[d] = lanes[d];
      for (int a = 0; a < 3; ++a) grad[a][d] = lanes[4 * (a + 1) + d];
    }
    if constexpr (kSharedLane) {
      weight = lanes[D];
      for (int a = 0; a < 3; ++a) weight_grad[a][0] = lanes[4 * (a + 1) + D];
    } else if constexpr (kRational) {
      detail::cell_horner_gradient_avx2<1, false>(denominator, nullptr, s, lanes);
      weight = lanes[0];
      for (int a = 0; a < 3; ++a) weight_grad[a][0] = lanes[4 * (a + 1)];
    }
  } else
#endif
  {
    horner3_gradient<D>(numerator, s, value, grad);
    if (kRational) horner3_gradient<1>(denominator, s, &weight, weight_grad);
  }
  if (kRational) {
    for (int d = 0; d < D; ++d) value[d] /= weight;
  }
  for (int a = 0; a < 3; ++a) {
    const double inverse_width = inverse_widths_[a][k[a]];
    for (int d = 0; d < D; ++d) {
      double g = grad[a][d];
      if (kRational) g = (g - value[d] * weight_grad[a][0]) / weight;
      jacobian[d + D * a] = g * inverse_width;
    }
  }
}

void TSpline::evaluate_to(const Eigen::Vector3d& uvw, TSplineForm form, double* value) const {
  const bool rational = form == TSplineForm::Rational;
  switch (dimension_) {
    case 1: rational ? evaluate_impl<1, true, false>(uvw, value, nullptr) : evaluate_impl<1, false, false>(uvw, value, nullptr); break;
    case 2: rational ? evaluate_impl<2, true, false>(uvw, value, nullptr) : evaluate_impl<2, false, false>(uvw, value, nullptr); break;
    case 3: rational ? evaluate_impl<3, true, false>(uvw, value, nullptr) : evaluate_impl<3, false, false>(uvw, value, nullptr); break;
    default: rational ? evaluate_impl<4, true, false>(uvw, value, nullptr) : evaluate_impl<4, false, false>(uvw, value, nullptr); break;
  }
}

void TSpline::evaluate_with_jacobian(const Eigen::Vector3d& uvw, TSplineForm form, double* value,
                                     double* jacobian) const {
  const bool rational = form == TSplineForm::Rational;
  switch (dimension_) {
    case 1: rational ? evaluate_impl<1, true, true>(uvw, value, jacobian) : evaluate_impl<1, false, true>(uvw, value, jacobian); break;
    case 2: rational ? evaluate_impl<2, true, true>(uvw, value, jacobian) : evaluate_impl<2, false, true>(uvw, value, jacobian); break;
    case 3: rational ? evaluate_impl<3, true, true>(uvw, value, jacobian) : evaluate_impl<3, false, true>(uvw, value, jacobian); break;
    default: rational ? evaluate_impl<4, true, true>(uvw, value, jacobian) : evaluate_impl<4, false, true>(uvw, value, jacobian); break;
  }
}

Eigen::VectorXd TSpline::evaluate(const Eigen::Vector3d& uvw, TSplineForm form) const {
  Eigen::VectorXd value(dimension_);
  evaluate_to(uvw, form, value.data());
  return value;
}

Eigen::MatrixXd TSpline::jacobian(const Eigen::Vector3d& uvw, TSplineForm form) const {
  double value[4];
  Eigen::MatrixXd jac(dimension_, 3);
  evaluate_with_jacobian(uvw, form, value, jac.data());
  return jac;
}

// Stable counting sort by cell id carrying each row's local coordinates along: one pass over the
// cell ids when there are at most 2^16 cells, else two passes of 16 bits (cells < 2^26).
void TSpline::sort_rows(const Eigen::MatrixX3d& uvw, Eigen::Index begin, Eigen::Index end,
                        SortedRows& sorted) const {
  const std::size_t m = static_cast<std::size_t>(end - begin);
  // Compared in 64 bits: Eigen::Index is 32-bit on wasm32, where 2^32 - 1 does not fit it.
  if (static_cast<std::uint64_t>(end) > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("T-spline: a batch of more than 2^32 - 1 rows");
  }
  sorted.cell.resize(m);
  sorted.row.resize(m);
  sorted.local.resize(3 * m);
  int k[3];
  for (std::size_t i = 0; i < m; ++i) {
    const Eigen::Index row = begin + Eigen::Index(i);
    try {
      sorted.cell[i] = static_cast<std::uint32_t>(locate(uvw.row(row).transpose(), sorted.local.data() + 3 * i, k));
    } catch (const Error& e) {
      throw Error("row " + std::to_string(row) + ": " + e.what());
    }
    sorted.row[i] = static_cast<std::uint32_t>(row);
  }
  const bool one_pass = cells_.size() <= (std::size_t(1) << 16);
  sorted.next_cell.resize(m);
  sorted.next_row.resize(m);
  sorted.next_local.resize(3 * m);
  for (int pass = 0; pass < (one_pass ? 1 : 2); ++pass) {
    const int shift = 16 * pass;
    sorted.count.assign(one_pass ? cells_.size() : std::size_t(1) << 16, 0);
    std::uint32_t* count = sorted.count.data();
    for (std::size_t i = 0; i < m; ++i) ++count[(sorted.cell[i] >> shift) & 0xffff];
    std::uint32_t start = 0;
    for (std::size_t c = 0; c < sorted.count.size(); ++c) {
      const std::uint32_t n = count[c];
      count[c] = start;
      start += n;
    }
    for (std::size_t i = 0; i < m; ++i) {
      const std::uint32_t j = count[(sorted.cell[i] >> shift) & 0xffff]++;
      sorted.next_cell[j] = sorted.cell[i];
      sorted.next_row[j] = sorted.row[i];
      for (int a = 0; a < 3; ++a) sorted.next_local[3 * j + a] = sorted.local[3 * i + a];
    }
    sorted.cell.swap(sorted.next_cell);
    sorted.row.swap(sorted.next_row);
    sorted.local.swap(sorted.next_local);
  }
  sorted.rank.resize(m);
  for (std::size_t j = 0; j < m; ++j) sorted.rank[sorted.row[j] - std::size_t(begin)] = static_cast<std::uint32_t>(j);
}

// Rows of one cell share its polynomial: with AVX2, four rows a time run the Horner passes in the
// four lanes (cell_horner_points_avx2), each lane with the bits of the one-point evaluation.
template <int D, bool kRational, bool kJacobian>
void TSpline::evaluate_sorted(const SortedRows& sorted, double* out) const {
  constexpr int kChannels = kJacobian ? 4 * D : D;
  const std::size_t n = sorted.cell.size();
  const int n0 = int(breaks_[0].size() - 1), n1 = int(breaks_[1].size() - 1);
  std::size_t i = 0;
  while (i < n) {
    const int cell = int(sorted.cell[i]);
    std::size_t end = i;
    while (end < n && int(sorted.cell[end]) == cell) ++end;
    const int k[3] = {cell % n0, (cell / n0) % n1, cell / (n0 * n1)};
#if defined(VOLSPLINE_AVX2_KERNELS)
    if (avx2_ && has_cell_polynomials()) {
      const double* numerator = cell_numerator_.data() + std::size_t(cell) * 64 * D;
      const double* denominator = cell_denominator_.data() + std::size_t(cell) * 64;
      double s[12], num[16 * D], den[16];
      for (; i + 4 <= end; i += 4) {
        for (int p = 0; p < 4; ++p)
          for (int a = 0; a < 3; ++a) s[4 * a + p] = sorted.local[3 * (i + p) + a];
        if (!kJacobian) {
          detail::cell_horner_points_avx2<D>(numerator, s, num);
          if (kRational) detail::cell_horner_points_avx2<1>(denominator, s, den);
          for (int p = 0; p < 4; ++p) {
            double* value = out + (i + p) * kChannels;
            for (int d = 0; d < D; ++d) value[d] = num[4 * d + p];
            if (kRational) {
              const double inverse_weight = 1.0 / den[p];
              for (int d = 0; d < D; ++d) value[d] *= inverse_weight;
            }
          }
          continue;
        }
        detail::cell_horner_gradient_points_avx2<D>(numerator, s, num);
        if (kRational) detail::cell_horner_gradient_points_avx2<1>(denominator, s, den);
        for (int p = 0; p < 4; ++p) {
          double* value = out + (i + p) * kChannels;
          double* jacobian = value + D;
          const double weight = kRational ? den[p] : 1.0;
          for (int d = 0; d < D; ++d) value[d] = kRational ? num[4 * d + p] / weight : num[4 * d + p];
          for (int a = 0; a < 3; ++a) {
            const double inverse_width = inverse_widths_[a][k[a]];
            for (int d = 0; d < D; ++d) {
              double g = num[4 * (D * (1 + a) + d) + p];
              if (kRational) g = (g - value[d] * den[4 * (1 + a) + p]) / weight;
              jacobian[d + D * a] = g * inverse_width;
            }
          }
        }
      }
    }
#endif
    for (; i < end; ++i) {
      double* value = out + i * kChannels;
      evaluate_at<D, kRational, kJacobian>(cell, sorted.local.data() + 3 * i, k, value, value + D);
    }
  }
}

namespace {
// Rows sorted and evaluated together: the sorted rows, their results and the output rows they
// scatter to stay in L2, while a cell holds several rows of a chunk on the splines of interest.
// Rows per chunk: enough for several rows per cell, at most 2^18 (4 to 16 MB of results).
Eigen::Index batch_chunk(std::size_t num_cells) {
  return std::clamp<Eigen::Index>(8 * Eigen::Index(num_cells), 32768, 262144);
}
}  // namespace

Eigen::MatrixXd TSpline::evaluate_batch(const Eigen::MatrixX3d& uvw, TSplineForm form) const {
  Eigen::MatrixXd out;
  evaluate_batch(uvw, form, out);
  return out;
}

template <bool kJacobian, class Scatter>
void TSpline::evaluate_chunks(const Eigen::MatrixX3d& uvw, TSplineForm form, Scatter&& scatter) const {
  const int D = dimension_;
  SortedRows sorted;
  std::vector<double> result;
  const bool rational = form == TSplineForm::Rational;
  const Eigen::Index chunk = batch_chunk(cells_.size());
  for (Eigen::Index begin = 0; begin < uvw.rows(); begin += chunk) {
    const Eigen::Index end = std::min(uvw.rows(), begin + chunk);
    sort_rows(uvw, begin, end, sorted);
    result.resize(std::size_t(end - begin) * (kJacobian ? 4 : 1) * D);
    double* r = result.data();
    switch (D) {
      case 1: rational ? evaluate_sorted<1, true, kJacobian>(sorted, r) : evaluate_sorted<1, false, kJacobian>(sorted, r); break;
      case 2: rational ? evaluate_sorted<2, true, kJacobian>(sorted, r) : evaluate_sorted<2, false, kJacobian>(sorted, r); break;
      case 3: rational ? evaluate_sorted<3, true, kJacobian>(sorted, r) : evaluate_sorted<3, false, kJacobian>(sorted, r); break;
      default: rational ? evaluate_sorted<4, true, kJacobian>(sorted, r) : evaluate_sorted<4, false, kJacobian>(sorted, r); break;
    }
    scatter(begin, end, sorted, static_cast<const double*>(r));
  }
}

// The results come out in cell order; each output row gathers its own (one read of D or 4D
// consecutive doubles) so the writes to the column-major outputs run in row order.
void TSpline::evaluate_batch(const Eigen::MatrixX3d& uvw, TSplineForm form, Eigen::MatrixXd& out) const {
  const int D = dimension_;
  out.resize(uvw.rows(), D);
  evaluate_chunks<false>(uvw, form, [&](Eigen::Index begin, Eigen::Index end, const SortedRows& sorted, const double* r) {
    for (int d = 0; d < D; ++d) {
      for (Eigen::Index i = begin; i < end; ++i) out(i, d) = r[std::size_t(sorted.rank[i - begin]) * D + d];
    }
  });
}

void TSpline::evaluate_batch_with_jacobian(const Eigen::MatrixX3d& uvw, TSplineForm form, Eigen::MatrixXd& values,
                                           Eigen::MatrixXd& jacobians) const {
  const int D = dimension_;
  values.resize(uvw.rows(), D);
  jacobians.resize(uvw.rows(), 3 * D);
  evaluate_chunks<true>(uvw, form, [&](Eigen::Index begin, Eigen::Index end, const SortedRows& sorted, const double* r) {
    for (Eigen::Index i = begin; i < end; ++i) {
      const double* p = r + std::size_t(sorted.rank[i - begin]) * 4 * D;
      for (int d = 0; d < D; ++d) values(i, d) = p[d];
      for (int c = 0; c < 3 * D; ++c) jacobians(i, c) = p[D + c];
    }
  });
}

template <int D>
void TSpline::evaluate_lattice_impl(
    const std::array<std::vector<double>, 3>& coords,
    const std::function<void(int, int, int, const double*, const double*)>& visit) const {
  // Per axis, the runs of lattice coordinates in one grid interval (the rule of locate()).
  std::array<std::vector<std::array<int, 3>>, 3> runs;  // {interval, first, end}
  std::array<std::vector<double>, 3> local;
  for (int a = 0; a < 3; ++a) {
    const std::vector<double>& b = breaks_[a];
    const int m = int(b.size() - 1);
    local[a].resize(coords[a].size());
    for (size_t i = 0; i < coords[a].size(); ++i) {
      const double t = coords[a][i];
      if (!(t >= b.front() && t <= b.back())) throw_outside_domain(a, t, b.front(), b.back());
      const int k = std::min(m - 1, int(std::upper_bound(b.begin(), b.end(), t) - b.begin()) - 1);
      local[a][i] = (t - b[k]) * inverse_widths_[a][k];
      if (runs[a].empty() || runs[a].back()[0] != k) runs[a].push_back({k, int(i), int(i)});
      assert(runs[a].back()[0] == k);
      runs[a].back()[2] = int(i) + 1;
    }
  }
  const int nc0 = int(breaks_[0].size() - 1), nc1 = int(breaks_[1].size() - 1);
  LatticeScratch scratch;
  double value[D], jacobian[3 * D];
  for (const auto& r2 : runs[2])
    for (const auto& r1 : runs[1])
      for (const auto& r0 : runs[0]) {
        const std::array<int, 3>* r[3] = {&r0, &r1, &r2};
        const size_t cell_id = size_t(r0[0]) + size_t(nc0) * (size_t(r1[0]) + size_t(nc1) * size_t(r2[0]));
        const Cell& cell = cells_[cell_id];
        int n[3];
        const double* s[3];
        double inverse_width[3];
        for (int a = 0; a < 3; ++a) {
          n[a] = (*r[a])[2] - (*r[a])[1];
          s[a] = local[a].data() + (*r[a])[1];
          inverse_width[a] = inverse_widths_[a][(*r[a])[0]];
        }
        if (has_cell_polynomials())
          lattice_cell_polynomial<D>(cell_numerator_.data() + cell_id * 64 * D, n, s, scratch);
        else
          lattice_cell<D>(cell, entries_.data(), cell_pieces_.data() + cell.piece_begin, pieces_,
                          weighted_points_.data(), n, s, scratch);
        for (int k = 0; k < n[2]; ++k)
          for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i) {
              const double* o = scratch.out.data() + ((size_t(k) * n[1] + j) * n[0] + i) * 4 * D;
              for (int d = 0; d < D; ++d) {
                value[d] = o[d];
                for (int a = 0; a < 3; ++a) jacobian[d + D * a] = o[(a + 1) * D + d] * inverse_width[a];
              }
              visit(r0[1] + i, r1[1] + j, r2[1] + k, value, jacobian);
            }
      }
}

void TSpline::evaluate_lattice_with_jacobian(
    const std::array<std::vector<double>, 3>& coords,
    const std::function<void(int, int, int, const double*, const double*)>& visit) const {
  switch (dimension_) {
    case 1: evaluate_lattice_impl<1>(coords, visit); break;
    case 2: evaluate_lattice_impl<2>(coords, visit); break;
    case 3: evaluate_lattice_impl<3>(coords, visit); break;
    default: evaluate_lattice_impl<4>(coords, visit); break;
  }
}

const TSpline::Cell& TSpline::piece_values(const Eigen::Vector3d& uvw, const std::array<int, 3>& order,
                                           PieceValues& out) const {
  double s[3];
  int k[3];
  const Cell& cell = cells_[locate(uvw, s, k)];
  const int total = cell.num_pieces[0] + cell.num_pieces[1] + cell.num_pieces[2];
  double* values = out.stack;
  if (total > PieceValues::kStack) {
    out.heap.resize(total);
    values = out.heap.data();
  }
  const std::uint32_t* ids = cell_pieces_.data() + cell.piece_begin;
  for (int a = 0, m = 0; a < 3; ++a) {
    out.axis[a] = values + m;
    for (int p = 0; p < cell.num_pieces[a]; ++p, ++m) {
      values[m] = piece_derivative(pieces_[a][ids[m]], s[a], order[a], inverse_widths_[a][k[a]]);
    }
  }
  return cell;
}

void TSpline::basis_at(const Eigen::Vector3d& uvw, const std::array<int, 3>& order,
                       std::vector<int>& function_ids, std::vector<double>& values) const {
  PieceValues pieces;
  const Cell& cell = piece_values(uvw, order, pieces);
  const double* const* axis_values = pieces.axis;
  const std::size_t count = cell.entry_end - cell.entry_begin;
  function_ids.resize(count);
  values.resize(count);
  const Entry* entries = entries_.data() + cell.entry_begin;
  for (std::size_t e = 0; e < count; ++e) {
    const Entry& entry = entries[e];
    function_ids[e] = static_cast<int>(entry.function);
    values[e] = axis_values[0][entry.piece[0]] * axis_values[1][entry.piece[1]] * axis_values[2][entry.piece[2]];
  }
}

void TSpline::basis_gradient_at(const Eigen::Vector3d& uvw, std::vector<int>& function_ids,
                                std::array<std::vector<double>, 3>& gradient) const {
  PieceValues values, slopes;
  const Cell& cell = piece_values(uvw, {0, 0, 0}, values);
  piece_values(uvw, {1, 1, 1}, slopes);
  const double* const* v = values.axis;
  const double* const* d = slopes.axis;
  const std::size_t count = cell.entry_end - cell.entry_begin;
  function_ids.resize(count);
  for (std::vector<double>& g : gradient) g.resize(count);
  const Entry* entries = entries_.data() + cell.entry_begin;
  for (std::size_t e = 0; e < count; ++e) {
    const Entry& entry = entries[e];
    const std::uint32_t i = entry.piece[0], j = entry.piece[1], k = entry.piece[2];
    function_ids[e] = static_cast<int>(entry.function);
    gradient[0][e] = d[0][i] * v[1][j] * v[2][k];
    gradient[1][e] = v[0][i] * d[1][j] * v[2][k];
    gradient[2][e] = v[0][i] * v[1][j] * d[2][k];
  }
}

int TSpline::cell_of(const Eigen::Vector3d& uvw) const {
  double s[3];
  int k[3];
  return locate(uvw, s, k);
}

void TSpline::cell_functions(int cell, std::vector<int>& function_ids) const {
  assert(cell >= 0 && cell < num_cells());
  const Cell& c = cells_[static_cast<std::size_t>(cell)];
  function_ids.resize(c.entry_end - c.entry_begin);
  for (std::uint32_t e = c.entry_begin; e < c.entry_end; ++e)
    function_ids[e - c.entry_begin] = static_cast<int>(entries_[e].function);
}

Eigen::VectorXd TSpline::derivative(const Eigen::Vector3d& uvw, const std::array<int, 3>& order) const {
  std::vector<int> ids;
  std::vector<double> values;
  basis_at(uvw, order, ids, values);
  Eigen::VectorXd out = Eigen::VectorXd::Zero(dimension_);
  for (size_t m = 0; m < ids.size(); ++m) {
    for (int d = 0; d < dimension_; ++d) out[d] += values[m] * weighted_points_[size_t(ids[m]) * dimension_ + d];
  }
  return out;
}

// The same products and summation order as Σ w_i·basis_at(uvw), without the lists.
double TSpline::weight_sum(const Eigen::Vector3d& uvw) const {
  PieceValues pieces;
  const Cell& cell = piece_values(uvw, {0, 0, 0}, pieces);
  const double* const* axis_values = pieces.axis;
  double sum = 0.0;
  const double* w = weights_.data();
  for (std::uint32_t e = cell.entry_begin; e < cell.entry_end; ++e) {
    const Entry& entry = entries_[e];
    sum += w[entry.function] *
           (axis_values[0][entry.piece[0]] * axis_values[1][entry.piece[1]] * axis_values[2][entry.piece[2]]);
  }
  return sum;
}

double TSpline::blending_function(int i, const Eigen::Vector3d& uvw) const {
  assert(i >= 0 && i < num_functions());
  double b = 1.0;
  for (int a = 0; a < 3; ++a) {
    const LocalKnots& r = knots_[i][a];
    const RightEnd end = r[4] == breaks_[a].back() ? RightEnd::Closed : RightEnd::Open;
    b *= cubic_basis(r, uvw[a], end);
  }
  return b;
}

TSpline from_bspline_volume(const BsplineVolume& volume, TSplineAcceleration acceleration) {
  const int n[3] = {volume.num_control(0), volume.num_control(1), volume.num_control(2)};
  std::vector<BlendingKnots> knots(size_t(n[0]) * n[1] * n[2]);
  for (int i2 = 0; i2 < n[2]; ++i2) {
    for (int i1 = 0; i1 < n[1]; ++i1) {
      for (int i0 = 0; i0 < n[0]; ++i0) {
        const int idx[3] = {i0, i1, i2};
        BlendingKnots& k = knots[volume.control_index(i0, i1, i2)];
        for (int a = 0; a < 3; ++a) {
          for (int m = 0; m < 5; ++m) k[a][m] = volume.knots(a)[idx[a] + m];
        }
      }
    }
  }
  Eigen::VectorXd weights = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(knots.size()));
  return TSpline(std::move(knots), std::move(weights), volume.control_points(), acceleration);
}

}  // namespace volspline::spline
