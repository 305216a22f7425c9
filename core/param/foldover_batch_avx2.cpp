// SPDX-License-Identifier: MIT
// foldover_kernel<4> and hex_corner_kernel (one or two hexes a call) compiled with -mavx2 (and without
// FMA: the lanes keep the scalar bits).
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

// The eight corners of H hexes: registers 2h (corners 0–3) and 2h + 1 (corners 4–7) of hex h.
// Two hexes side by side give the out-of-order core two independent chains (the Newton steps of
// x^(−1/3) are one long chain per register); every lane's operations stay those of one hex.
template <int H>
struct Lanes {
  __m256d r[2 * H];
};

template <int H>
inline Lanes<H> add(const Lanes<H>& a, const Lanes<H>& b) {
  Lanes<H> out;
  for (int k = 0; k < 2 * H; ++k) out.r[k] = _mm256_add_pd(a.r[k], b.r[k]);
  return out;
}
template <int H>
inline Lanes<H> sub(const Lanes<H>& a, const Lanes<H>& b) {
  Lanes<H> out;
  for (int k = 0; k < 2 * H; ++k) out.r[k] = _mm256_sub_pd(a.r[k], b.r[k]);
  return out;
}
template <int H>
inline Lanes<H> mul(const Lanes<H>& a, const Lanes<H>& b) {
  Lanes<H> out;
  for (int k = 0; k < 2 * H; ++k) out.r[k] = _mm256_mul_pd(a.r[k], b.r[k]);
  return out;
}
template <int H>
inline Lanes<H> div(const Lanes<H>& a, const Lanes<H>& b) {
  Lanes<H> out;
  for (int k = 0; k < 2 * H; ++k) out.r[k] = _mm256_div_pd(a.r[k], b.r[k]);
  return out;
}
template <int H>
inline Lanes<H> splat(double v) {
  Lanes<H> out;
  for (int k = 0; k < 2 * H; ++k) out.r[k] = _mm256_set1_pd(v);
  return out;
}

// Per lane c, the value at lane c with bit `axis` cleared (low) or set (high), within its hex.
template <int axis, int H>
inline Lanes<H> at_low(const Lanes<H>& v) {
  Lanes<H> out;
  for (int h = 0; h < H; ++h)
    for (int half = 0; half < 2; ++half) {
      const __m256d x = v.r[2 * h + half];
      if constexpr (axis == 0) out.r[2 * h + half] = _mm256_permute_pd(x, 0x0);
      if constexpr (axis == 1) out.r[2 * h + half] = _mm256_permute2f128_pd(x, x, 0x00);
      if constexpr (axis == 2) out.r[2 * h + half] = v.r[2 * h];
    }
  return out;
}
template <int axis, int H>
inline Lanes<H> at_high(const Lanes<H>& v) {
  Lanes<H> out;
  for (int h = 0; h < H; ++h)
    for (int half = 0; half < 2; ++half) {
      const __m256d x = v.r[2 * h + half];
      if constexpr (axis == 0) out.r[2 * h + half] = _mm256_permute_pd(x, 0xF);
      if constexpr (axis == 1) out.r[2 * h + half] = _mm256_permute2f128_pd(x, x, 0x11);
      if constexpr (axis == 2) out.r[2 * h + half] = v.r[2 * h + 1];
    }
  return out;
}

// Column `axis` of every corner's J (coordinate d): the +axis hex edge through the corner.
template <int axis, int H>
inline void edge_column(const Lanes<H> (&p)[3], const Lanes<H>& inv_h, Lanes<H> (&j)[3]) {
  for (int d = 0; d < 3; ++d) j[d] = mul(sub(at_high<axis>(p[d]), at_low<axis>(p[d])), inv_h);
}

// Node gradients of the edges along `axis`: each edge sums its corners' (masked) gradients, low
// corner first; the node at its high end gains it, the low one loses it.
template <int axis, int H>
inline void scatter_edges(const Lanes<H> (&g)[3], const Lanes<H>& mask, const Lanes<H>& inv_h, Lanes<H> (&grad)[3]) {
  // Lanes without bit `axis` are low ends: their term is negated.
  const __m256d flip_lo = axis == 0   ? _mm256_setr_pd(-0.0, 0.0, -0.0, 0.0)
                          : axis == 1 ? _mm256_setr_pd(-0.0, -0.0, 0.0, 0.0)
                                      : _mm256_set1_pd(-0.0);
  const __m256d flip_hi = axis == 0   ? _mm256_setr_pd(-0.0, 0.0, -0.0, 0.0)
                          : axis == 1 ? _mm256_setr_pd(-0.0, -0.0, 0.0, 0.0)
                                      : _mm256_setzero_pd();
  for (int d = 0; d < 3; ++d) {
    Lanes<H> masked;
    for (int k = 0; k < 2 * H; ++k) masked.r[k] = _mm256_and_pd(g[d].r[k], mask.r[k]);
    const Lanes<H> term = mul(add(add(splat<H>(0.0), at_low<axis>(masked)), at_high<axis>(masked)), inv_h);
    for (int k = 0; k < 2 * H; ++k)
      grad[d].r[k] = _mm256_add_pd(grad[d].r[k], _mm256_xor_pd(term.r[k], k % 2 ? flip_hi : flip_lo));
  }
}

// hex_corner_kernel in AVX2 registers for H hexes at once, lane c of hex h = its corner c: every
// operation of the portable loops in the same order (no FMA), so the same bits.
template <int H>
inline void hex_corner_kernels(const double (*const* p)[3], const double* inv_h, double eps2, double theta,
                               const unsigned* corners, double* const* e, double (*const* grad)[3]) {
  Lanes<H> inv_h4;
  for (int k = 0; k < 2 * H; ++k) inv_h4.r[k] = _mm256_set1_pd(inv_h[k / 2]);
  Lanes<H> pos[3];
  for (int h = 0; h < H; ++h)
    for (int d = 0; d < 3; ++d) {
      const double(*q)[3] = p[h];
      pos[d].r[2 * h] = _mm256_setr_pd(q[0][d], q[1][d], q[2][d], q[3][d]);
      pos[d].r[2 * h + 1] = _mm256_setr_pd(q[4][d], q[5][d], q[6][d], q[7][d]);
    }
  Lanes<H> j[3][3];  // [axis][coordinate]
  edge_column<0>(pos, inv_h4, j[0]);
  edge_column<1>(pos, inv_h4, j[1]);
  edge_column<2>(pos, inv_h4, j[2]);
  const double shape = 1.0 - theta;
  // Column a of cof(J): the cross product of the other two columns (column 0 gives det J; the
  // others only the gradient).
  Lanes<H> cof[3][3];
  auto cofactor_column = [&](int a) {
    const Lanes<H>(&u)[3] = j[(a + 1) % 3];
    const Lanes<H>(&v)[3] = j[(a + 2) % 3];
    for (int d = 0; d < 3; ++d)
      cof[a][d] = sub(mul(u[(d + 1) % 3], v[(d + 2) % 3]), mul(u[(d + 2) % 3], v[(d + 1) % 3]));
  };
  cofactor_column(0);
  const Lanes<H> det = add(add(mul(j[0][0], cof[0][0]), mul(j[0][1], cof[0][1])), mul(j[0][2], cof[0][2]));
  Lanes<H> tr = add(add(mul(j[0][0], j[0][0]), mul(j[0][1], j[0][1])), mul(j[0][2], j[0][2]));
  tr = add(splat<H>(0.0), tr);
  for (int a = 1; a < 3; ++a) tr = add(tr, add(add(mul(j[a][0], j[a][0]), mul(j[a][1], j[a][1])), mul(j[a][2], j[a][2])));
  const __m256d eps2_4 = _mm256_set1_pd(eps2);
  const Lanes<H> det2 = mul(det, det);
  Lanes<H> root, chi, y;
  for (int k = 0; k < 2 * H; ++k) root.r[k] = _mm256_sqrt_pd(_mm256_add_pd(eps2_4, det2.r[k]));
  const Lanes<H> positive = mul(splat<H>(0.5), add(det, root));
  const __m256d half_eps2 = _mm256_mul_pd(_mm256_set1_pd(0.5), eps2_4);
  for (int k = 0; k < 2 * H; ++k) {
    chi.r[k] = barrier_chi4(det.r[k], root.r[k], positive.r[k], half_eps2);
    y.r[k] = inverse_cbrt_guess4(chi.r[k]);
  }
  const Lanes<H> four = splat<H>(4.0), third = splat<H>(1.0 / 3.0);
  for (int step = 0; step < 4; ++step) y = mul(mul(y, sub(four, mul(chi, mul(mul(y, y), y)))), third);
  const Lanes<H> inv_chi23 = mul(y, y), inv_chi = mul(inv_chi23, y);
  const Lanes<H> det2p1 = add(det2, splat<H>(1.0));
  const Lanes<H> energy = add(mul(mul(splat<H>(shape), tr), inv_chi23), mul(mul(splat<H>(theta), det2p1), inv_chi));
  for (int h = 0; h < H; ++h) {
    _mm256_storeu_pd(e[h], energy.r[2 * h]);
    _mm256_storeu_pd(e[h] + 4, energy.r[2 * h + 1]);
  }
  if (!grad) return;
  cofactor_column(1);
  cofactor_column(2);
  const Lanes<H> dchi = div(chi, root);
  const Lanes<H> ja = mul(splat<H>(2.0 * shape), inv_chi23);
  const Lanes<H> first = mul(mul(mul(mul(mul(splat<H>(-(2.0 / 3.0)), splat<H>(shape)), tr), inv_chi23), inv_chi), dchi);
  const Lanes<H> second =
      mul(splat<H>(theta), sub(mul(mul(splat<H>(2.0), det), inv_chi), mul(mul(mul(det2p1, dchi), inv_chi), inv_chi)));
  const Lanes<H> jb = add(first, second);
  const __m256i bit = _mm256_setr_epi64x(1, 2, 4, 8);
  Lanes<H> mask;
  for (int h = 0; h < H; ++h) {
    const __m256i flags = _mm256_set1_epi64x(corners[h]);
    mask.r[2 * h] = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(flags, bit), bit));
    mask.r[2 * h + 1] =
        _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(_mm256_srli_epi64(flags, 4), bit), bit));
  }
  Lanes<H> g[3][3];
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d < 3; ++d) g[a][d] = add(mul(ja, j[a][d]), mul(jb, cof[a][d]));
  Lanes<H> node[3] = {splat<H>(0.0), splat<H>(0.0), splat<H>(0.0)};
  scatter_edges<0>(g[0], mask, inv_h4, node);
  scatter_edges<1>(g[1], mask, inv_h4, node);
  scatter_edges<2>(g[2], mask, inv_h4, node);
  for (int h = 0; h < H; ++h) {
    alignas(32) double out[3][8];
    for (int d = 0; d < 3; ++d) {
      _mm256_store_pd(out[d], node[d].r[2 * h]);
      _mm256_store_pd(out[d] + 4, node[d].r[2 * h + 1]);
    }
    for (int q = 0; q < 8; ++q)
      for (int d = 0; d < 3; ++d) grad[h][q][d] = out[d][q];
  }
}

}  // namespace

void hex_corner_kernel_avx2(const double (*p)[3], double inv_h, double eps2, double theta, unsigned corners,
                            double* e, double (*grad)[3]) {
  hex_corner_kernels<1>(&p, &inv_h, eps2, theta, &corners, &e, grad ? &grad : nullptr);
}

void hex_corner_kernel2_avx2(const double (*const p[2])[3], const double inv_h[2], double eps2, double theta,
                             const unsigned corners[2], double* const e[2], double (*const grad[2])[3]) {
  hex_corner_kernels<2>(p, inv_h, eps2, theta, corners, e, grad && grad[0] ? grad : nullptr);
}
#endif

}  // namespace volspline::param::detail
