// SPDX-License-Identifier: MIT
// foldover_kernel<4> and hex_corner_kernel compiled with -mavx2 (and without FMA: the lanes keep the scalar bits).
#include "core/param/foldover_kernel.h"

#if defined(VOLSPLINE_AVX2_KERNELS)
#include <immintrin.h>
#endif

namespace volspline::param::detail {

#if defined(VOLSPLINE_AVX2_KERNELS)
namespace {

// cbrt_positive per lane: the same integer guess on the bit pattern (a 32×32 → 64-bit product
// per lane) and the same three Halley steps.
inline __m256d cbrt_positive4(__m256d y) {
  const __m256d smallest = _mm256_set1_pd(2.2250738585072014e-308);
  y = _mm256_blendv_pd(y, smallest, _mm256_cmp_pd(y, smallest, _CMP_LT_OQ));
  const __m256i high = _mm256_srli_epi64(_mm256_castpd_si256(y), 32);
  const __m256i third = _mm256_srli_epi64(_mm256_mul_epu32(high, _mm256_set1_epi64x(0xAAAAAAABll)), 33);
  __m256d r = _mm256_castsi256_pd(_mm256_slli_epi64(_mm256_add_epi64(third, _mm256_set1_epi64x(715094163ll)), 32));
  const __m256d two = _mm256_set1_pd(2.0);
  for (int step = 0; step < 3; ++step) {
    const __m256d r3 = _mm256_mul_pd(_mm256_mul_pd(r, r), r);
    r = _mm256_sub_pd(r, _mm256_mul_pd(r, _mm256_div_pd(_mm256_sub_pd(r3, y), _mm256_add_pd(_mm256_mul_pd(two, r3), y))));
  }
  return r;
}

}  // namespace

// foldover_kernel<4> in AVX2 registers, lane l = element l: every operation of the portable
// loops in the same order (no FMA), so the same bits.
void foldover_kernel4_avx2(const double* j, double eps, double theta, double* energy, double* gradient) {
  __m256d m[9];  // entry row + 3·col
  for (int k = 0; k < 9; ++k) m[k] = _mm256_loadu_pd(j + 4 * k);
  auto at = [&](int row, int col) { return m[row + 3 * col]; };
  const __m256d d = _mm256_add_pd(
      _mm256_sub_pd(
          _mm256_mul_pd(at(0, 0), _mm256_sub_pd(_mm256_mul_pd(at(1, 1), at(2, 2)), _mm256_mul_pd(at(2, 1), at(1, 2)))),
          _mm256_mul_pd(at(0, 1), _mm256_sub_pd(_mm256_mul_pd(at(1, 0), at(2, 2)), _mm256_mul_pd(at(2, 0), at(1, 2))))),
      _mm256_mul_pd(at(0, 2), _mm256_sub_pd(_mm256_mul_pd(at(1, 0), at(2, 1)), _mm256_mul_pd(at(2, 0), at(1, 1)))));
  const __m256d d2 = _mm256_mul_pd(d, d);
  const __m256d root = _mm256_sqrt_pd(_mm256_add_pd(_mm256_set1_pd(eps * eps), d2));
  const __m256d half = _mm256_set1_pd(0.5);
  const __m256d x_d = _mm256_mul_pd(half, _mm256_add_pd(d, root));
  __m256d tr = _mm256_setzero_pd();
  for (int k = 0; k < 9; ++k) tr = _mm256_add_pd(tr, _mm256_mul_pd(m[k], m[k]));
  const __m256d x23 = cbrt_positive4(_mm256_mul_pd(x_d, x_d));
  const double shape = 1.0 - theta;
  const __m256d theta4 = _mm256_set1_pd(theta), one = _mm256_set1_pd(1.0);
  const __m256d d2p1 = _mm256_add_pd(d2, one);
  _mm256_storeu_pd(energy, _mm256_add_pd(_mm256_div_pd(_mm256_mul_pd(_mm256_set1_pd(shape), tr), x23),
                                         _mm256_div_pd(_mm256_mul_pd(theta4, d2p1), x_d)));
  if (!gradient) return;
  const __m256d dchi = _mm256_mul_pd(half, _mm256_add_pd(one, _mm256_div_pd(d, root)));
  const __m256d a = _mm256_div_pd(_mm256_set1_pd(shape * 2.0), x23);
  const __m256d first = _mm256_mul_pd(
      _mm256_div_pd(_mm256_mul_pd(_mm256_set1_pd(-shape * (2.0 / 3.0)), tr), _mm256_mul_pd(x23, x_d)), dchi);
  const __m256d second = _mm256_mul_pd(
      theta4, _mm256_sub_pd(_mm256_div_pd(_mm256_mul_pd(_mm256_set1_pd(2.0), d), x_d),
                            _mm256_div_pd(_mm256_mul_pd(d2p1, dchi), _mm256_mul_pd(x_d, x_d))));
  const __m256d b = _mm256_add_pd(first, second);
  for (int col = 0; col < 3; ++col) {
    const int c1 = (col + 1) % 3, c2 = (col + 2) % 3;
    for (int row = 0; row < 3; ++row) {
      const int r1 = (row + 1) % 3, r2 = (row + 2) % 3;
      const __m256d cof = _mm256_sub_pd(_mm256_mul_pd(at(r1, c1), at(r2, c2)), _mm256_mul_pd(at(r2, c1), at(r1, c2)));
      _mm256_storeu_pd(gradient + 4 * (row + 3 * col), _mm256_add_pd(_mm256_mul_pd(a, at(row, col)), _mm256_mul_pd(b, cof)));
    }
  }
}

namespace {

// inverse_cbrt_guess per lane: the same integer arithmetic, bits / 3 as the high half of the
// 128-bit product with ⌈2⁶⁵/3⌉ (exact for every 64-bit value) from four 32×32 → 64-bit products,
// so the guess needs no round trip through memory and the scalar multiplier.
inline __m256d inverse_cbrt_guess4(__m256d x) {
  const __m256i bits = _mm256_castpd_si256(x);
  const __m256i m_high = _mm256_set1_epi64x(0xAAAAAAAAll), m_low = _mm256_set1_epi64x(0xAAAAAAABll);
  const __m256i low32 = _mm256_set1_epi64x(0xFFFFFFFFll);
  const __m256i b_high = _mm256_srli_epi64(bits, 32);
  const __m256i ll = _mm256_mul_epu32(bits, m_low), hl = _mm256_mul_epu32(b_high, m_low);
  const __m256i lh = _mm256_mul_epu32(bits, m_high), hh = _mm256_mul_epu32(b_high, m_high);
  const __m256i middle = _mm256_add_epi64(_mm256_add_epi64(_mm256_and_si256(hl, low32), _mm256_and_si256(lh, low32)),
                                          _mm256_srli_epi64(ll, 32));
  const __m256i high = _mm256_add_epi64(_mm256_add_epi64(hh, _mm256_srli_epi64(hl, 32)),
                                        _mm256_add_epi64(_mm256_srli_epi64(lh, 32), _mm256_srli_epi64(middle, 32)));
  const __m256i third = _mm256_srli_epi64(high, 1);
  return _mm256_castsi256_pd(_mm256_sub_epi64(_mm256_set1_epi64x(0x553edc82c19c9000ll), third));
}

// χ's cancellation-free branch 0.5·ε²/(√(ε² + D²) − D), where a lane has D < 0 (or NaN); the
// other lanes take (D + √(ε² + D²))/2, so a register of unfolded corners needs no division.
inline __m256d barrier_chi4(__m256d det, __m256d root, __m256d positive, __m256d half_eps2) {
  const __m256d unfolded = _mm256_cmp_pd(det, _mm256_setzero_pd(), _CMP_GE_OQ);
  if (_mm256_movemask_pd(unfolded) == 0xF) return positive;
  return _mm256_blendv_pd(_mm256_div_pd(half_eps2, _mm256_sub_pd(root, det)), positive, unfolded);
}

// Eight corners as two registers: corners 0–3 and 4–7.
struct Lanes {
  __m256d lo, hi;
};

inline Lanes add(const Lanes& a, const Lanes& b) { return {_mm256_add_pd(a.lo, b.lo), _mm256_add_pd(a.hi, b.hi)}; }
inline Lanes sub(const Lanes& a, const Lanes& b) { return {_mm256_sub_pd(a.lo, b.lo), _mm256_sub_pd(a.hi, b.hi)}; }
inline Lanes mul(const Lanes& a, const Lanes& b) { return {_mm256_mul_pd(a.lo, b.lo), _mm256_mul_pd(a.hi, b.hi)}; }
inline Lanes div(const Lanes& a, const Lanes& b) { return {_mm256_div_pd(a.lo, b.lo), _mm256_div_pd(a.hi, b.hi)}; }
inline Lanes splat(double v) { return {_mm256_set1_pd(v), _mm256_set1_pd(v)}; }

// Per lane c, the value at lane c with bit `axis` cleared (low) or set (high).
template <int axis>
inline Lanes at_low(const Lanes& v) {
  if constexpr (axis == 0) return {_mm256_permute_pd(v.lo, 0x0), _mm256_permute_pd(v.hi, 0x0)};
  if constexpr (axis == 1) return {_mm256_permute2f128_pd(v.lo, v.lo, 0x00), _mm256_permute2f128_pd(v.hi, v.hi, 0x00)};
  if constexpr (axis == 2) return {v.lo, v.lo};
}
template <int axis>
inline Lanes at_high(const Lanes& v) {
  if constexpr (axis == 0) return {_mm256_permute_pd(v.lo, 0xF), _mm256_permute_pd(v.hi, 0xF)};
  if constexpr (axis == 1) return {_mm256_permute2f128_pd(v.lo, v.lo, 0x11), _mm256_permute2f128_pd(v.hi, v.hi, 0x11)};
  if constexpr (axis == 2) return {v.hi, v.hi};
}

// Column `axis` of every corner's J (coordinate d): the +axis hex edge through the corner.
template <int axis>
inline void edge_column(const Lanes (&p)[3], const __m256d inv_h, Lanes (&j)[3]) {
  for (int d = 0; d < 3; ++d) {
    const Lanes e = sub(at_high<axis>(p[d]), at_low<axis>(p[d]));
    j[d] = {_mm256_mul_pd(e.lo, inv_h), _mm256_mul_pd(e.hi, inv_h)};
  }
}

// Node gradients of the edges along `axis`: each edge sums its corners' (masked) gradients, low
// corner first; the node at its high end gains it, the low one loses it.
template <int axis>
inline void scatter_edges(const Lanes (&g)[3], const Lanes& mask, const __m256d inv_h, Lanes (&grad)[3]) {
  const __m256d sign = _mm256_set1_pd(-0.0);
  // Lanes without bit `axis` are low ends: their term is negated.
  const Lanes flip = axis == 0   ? Lanes{_mm256_setr_pd(-0.0, 0.0, -0.0, 0.0), _mm256_setr_pd(-0.0, 0.0, -0.0, 0.0)}
                     : axis == 1 ? Lanes{_mm256_setr_pd(-0.0, -0.0, 0.0, 0.0), _mm256_setr_pd(-0.0, -0.0, 0.0, 0.0)}
                                 : Lanes{sign, _mm256_setzero_pd()};
  for (int d = 0; d < 3; ++d) {
    const Lanes masked = {_mm256_and_pd(g[d].lo, mask.lo), _mm256_and_pd(g[d].hi, mask.hi)};
    const Lanes sum = add(add(splat(0.0), at_low<axis>(masked)), at_high<axis>(masked));
    const Lanes term = {_mm256_mul_pd(sum.lo, inv_h), _mm256_mul_pd(sum.hi, inv_h)};
    grad[d] = add(grad[d], Lanes{_mm256_xor_pd(term.lo, flip.lo), _mm256_xor_pd(term.hi, flip.hi)});
  }
}

}  // namespace

// hex_corner_kernel in AVX2 registers, lane c = corner c: every operation of the portable loops
// in the same order (no FMA), so the same bits.
void hex_corner_kernel_avx2(const double (*p)[3], double inv_h, double eps2, double theta, unsigned corners,
                            double* e, double (*grad)[3]) {
  const __m256d inv_h4 = _mm256_set1_pd(inv_h);
  Lanes pos[3];
  for (int d = 0; d < 3; ++d)
    pos[d] = {_mm256_setr_pd(p[0][d], p[1][d], p[2][d], p[3][d]), _mm256_setr_pd(p[4][d], p[5][d], p[6][d], p[7][d])};
  Lanes j[3][3];  // [axis][coordinate]
  edge_column<0>(pos, inv_h4, j[0]);
  edge_column<1>(pos, inv_h4, j[1]);
  edge_column<2>(pos, inv_h4, j[2]);
  const double shape = 1.0 - theta;
  // Column a of cof(J): the cross product of the other two columns (column 0 gives det J; the
  // others only the gradient).
  Lanes cof[3][3];
  auto cofactor_column = [&](int a) {
    const Lanes(&u)[3] = j[(a + 1) % 3];
    const Lanes(&v)[3] = j[(a + 2) % 3];
    for (int d = 0; d < 3; ++d)
      cof[a][d] = sub(mul(u[(d + 1) % 3], v[(d + 2) % 3]), mul(u[(d + 2) % 3], v[(d + 1) % 3]));
  };
  cofactor_column(0);
  const Lanes det = add(add(mul(j[0][0], cof[0][0]), mul(j[0][1], cof[0][1])), mul(j[0][2], cof[0][2]));
  Lanes tr = add(add(mul(j[0][0], j[0][0]), mul(j[0][1], j[0][1])), mul(j[0][2], j[0][2]));
  tr = add(splat(0.0), tr);
  for (int a = 1; a < 3; ++a) tr = add(tr, add(add(mul(j[a][0], j[a][0]), mul(j[a][1], j[a][1])), mul(j[a][2], j[a][2])));
  const Lanes eps2_4 = splat(eps2);
  const Lanes det2 = mul(det, det);
  const Lanes root = {_mm256_sqrt_pd(_mm256_add_pd(eps2_4.lo, det2.lo)), _mm256_sqrt_pd(_mm256_add_pd(eps2_4.hi, det2.hi))};
  const Lanes positive = mul(splat(0.5), add(det, root));
  const __m256d half_eps2 = _mm256_mul_pd(_mm256_set1_pd(0.5), eps2_4.lo);
  const Lanes chi = {barrier_chi4(det.lo, root.lo, positive.lo, half_eps2),
                     barrier_chi4(det.hi, root.hi, positive.hi, half_eps2)};
  Lanes y = {inverse_cbrt_guess4(chi.lo), inverse_cbrt_guess4(chi.hi)};
  const Lanes four = splat(4.0), third = splat(1.0 / 3.0);
  for (int step = 0; step < 4; ++step) y = mul(mul(y, sub(four, mul(chi, mul(mul(y, y), y)))), third);
  const Lanes inv_chi23 = mul(y, y), inv_chi = mul(inv_chi23, y);
  const Lanes det2p1 = add(det2, splat(1.0));
  const Lanes energy = add(mul(mul(splat(shape), tr), inv_chi23), mul(mul(splat(theta), det2p1), inv_chi));
  _mm256_storeu_pd(e, energy.lo);
  _mm256_storeu_pd(e + 4, energy.hi);
  if (!grad) return;
  cofactor_column(1);
  cofactor_column(2);
  const Lanes dchi = div(chi, root);
  const Lanes ja = mul(splat(2.0 * shape), inv_chi23);
  const Lanes first = mul(mul(mul(mul(mul(splat(-(2.0 / 3.0)), splat(shape)), tr), inv_chi23), inv_chi), dchi);
  const Lanes second =
      mul(splat(theta), sub(mul(mul(splat(2.0), det), inv_chi), mul(mul(mul(det2p1, dchi), inv_chi), inv_chi)));
  const Lanes jb = add(first, second);
  const __m256i bit = _mm256_setr_epi64x(1, 2, 4, 8);
  const __m256i flags = _mm256_set1_epi64x(corners);
  const Lanes mask = {
      _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(flags, bit), bit)),
      _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(_mm256_srli_epi64(flags, 4), bit), bit))};
  Lanes g[3][3];
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d < 3; ++d) g[a][d] = add(mul(ja, j[a][d]), mul(jb, cof[a][d]));
  Lanes node[3] = {splat(0.0), splat(0.0), splat(0.0)};
  scatter_edges<0>(g[0], mask, inv_h4, node);
  scatter_edges<1>(g[1], mask, inv_h4, node);
  scatter_edges<2>(g[2], mask, inv_h4, node);
  alignas(32) double out[3][8];
  for (int d = 0; d < 3; ++d) {
    _mm256_store_pd(out[d], node[d].lo);
    _mm256_store_pd(out[d] + 4, node[d].hi);
  }
  for (int q = 0; q < 8; ++q)
    for (int d = 0; d < 3; ++d) grad[q][d] = out[d][q];
}
#endif

}  // namespace volspline::param::detail
