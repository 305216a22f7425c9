// SPDX-License-Identifier: MIT
// hex_corner_kernel (one or two hexes a call) compiled with -mavx512f: a hex's 8 corners fill one
// register. Built with -ffp-contract=off, since AVX-512F brings fused multiply-adds with it (no
// -mno-fma: clang would drop AVX-512F with it): the lanes keep the scalar bits.
#include "core/param/foldover_kernel.h"

#if defined(VOLSPLINE_AVX512_KERNELS)
#include <immintrin.h>
#endif

namespace volspline::param::detail {

#if defined(VOLSPLINE_AVX512_KERNELS)
namespace {

// inverse_cbrt_guess per lane, as inverse_cbrt_guess4 of the AVX2 build: bits / 3 as the high
// half of the 128-bit product with ⌈2⁶⁵/3⌉ from four 32×32 → 64-bit products (exact integers).
inline __m512d inverse_cbrt_guess8(__m512d x) {
  const __m512i bits = _mm512_castpd_si512(x);
  const __m512i m_high = _mm512_set1_epi64(0xAAAAAAAAll), m_low = _mm512_set1_epi64(0xAAAAAAABll);
  const __m512i low32 = _mm512_set1_epi64(0xFFFFFFFFll);
  const __m512i b_high = _mm512_srli_epi64(bits, 32);
  const __m512i ll = _mm512_mul_epu32(bits, m_low), hl = _mm512_mul_epu32(b_high, m_low);
  const __m512i lh = _mm512_mul_epu32(bits, m_high), hh = _mm512_mul_epu32(b_high, m_high);
  const __m512i middle = _mm512_add_epi64(_mm512_add_epi64(_mm512_and_si512(hl, low32), _mm512_and_si512(lh, low32)),
                                          _mm512_srli_epi64(ll, 32));
  const __m512i high = _mm512_add_epi64(_mm512_add_epi64(hh, _mm512_srli_epi64(hl, 32)),
                                        _mm512_add_epi64(_mm512_srli_epi64(lh, 32), _mm512_srli_epi64(middle, 32)));
  const __m512i third = _mm512_srli_epi64(high, 1);
  return _mm512_castsi512_pd(_mm512_sub_epi64(_mm512_set1_epi64(0x553edc82c19c9000ll), third));
}

// χ's cancellation-free branch 0.5·ε²/(√(ε² + D²) − D) where a corner has D < 0 (or NaN); a hex
// whose 8 corners have D ≥ 0 needs no division.
inline __m512d barrier_chi8(__m512d det, __m512d root, __m512d positive, __m512d half_eps2) {
  const __mmask8 unfolded = _mm512_cmp_pd_mask(det, _mm512_setzero_pd(), _CMP_GE_OQ);
  if (unfolded == 0xFF) return positive;
  return _mm512_mask_blend_pd(unfolded, _mm512_div_pd(half_eps2, _mm512_sub_pd(root, det)), positive);
}

// The corners of H hexes, register h = hex h (lane c = corner c). Two hexes give the core two
// independent chains, as in the AVX2 build.
template <int H>
struct Lanes {
  __m512d r[H];
};

template <int H>
inline Lanes<H> add(const Lanes<H>& a, const Lanes<H>& b) {
  Lanes<H> out;
  for (int k = 0; k < H; ++k) out.r[k] = _mm512_add_pd(a.r[k], b.r[k]);
  return out;
}
template <int H>
inline Lanes<H> sub(const Lanes<H>& a, const Lanes<H>& b) {
  Lanes<H> out;
  for (int k = 0; k < H; ++k) out.r[k] = _mm512_sub_pd(a.r[k], b.r[k]);
  return out;
}
template <int H>
inline Lanes<H> mul(const Lanes<H>& a, const Lanes<H>& b) {
  Lanes<H> out;
  for (int k = 0; k < H; ++k) out.r[k] = _mm512_mul_pd(a.r[k], b.r[k]);
  return out;
}
template <int H>
inline Lanes<H> div(const Lanes<H>& a, const Lanes<H>& b) {
  Lanes<H> out;
  for (int k = 0; k < H; ++k) out.r[k] = _mm512_div_pd(a.r[k], b.r[k]);
  return out;
}
template <int H>
inline Lanes<H> splat(double v) {
  Lanes<H> out;
  for (int k = 0; k < H; ++k) out.r[k] = _mm512_set1_pd(v);
  return out;
}

// Per lane c, the value at lane c with bit `axis` cleared (low) or set (high).
template <int axis, int H>
inline Lanes<H> at_low(const Lanes<H>& v) {
  Lanes<H> out;
  for (int k = 0; k < H; ++k) {
    if constexpr (axis == 0) out.r[k] = _mm512_permute_pd(v.r[k], 0x00);
    if constexpr (axis == 1) out.r[k] = _mm512_permutex_pd(v.r[k], 0x44);
    if constexpr (axis == 2) out.r[k] = _mm512_shuffle_f64x2(v.r[k], v.r[k], 0x44);
  }
  return out;
}
template <int axis, int H>
inline Lanes<H> at_high(const Lanes<H>& v) {
  Lanes<H> out;
  for (int k = 0; k < H; ++k) {
    if constexpr (axis == 0) out.r[k] = _mm512_permute_pd(v.r[k], 0xFF);
    if constexpr (axis == 1) out.r[k] = _mm512_permutex_pd(v.r[k], 0xEE);
    if constexpr (axis == 2) out.r[k] = _mm512_shuffle_f64x2(v.r[k], v.r[k], 0xEE);
  }
  return out;
}

// Column `axis` of every corner's J (coordinate d): the +axis hex edge through the corner.
template <int axis, int H>
inline void edge_column(const Lanes<H> (&p)[3], const Lanes<H>& inv_h, Lanes<H> (&j)[3]) {
  for (int d = 0; d < 3; ++d) j[d] = mul(sub(at_high<axis>(p[d]), at_low<axis>(p[d])), inv_h);
}

// Node gradients of the edges along `axis`: each edge sums its corners' (masked) gradients, low
// corner first; the node at its high end gains it, the low one loses it (sign flipped in the
// lanes without bit `axis`).
template <int axis, int H>
inline void scatter_edges(const Lanes<H> (&g)[3], const __mmask8 (&mask)[H], const Lanes<H>& inv_h,
                          Lanes<H> (&grad)[3]) {
  constexpr long long m = static_cast<long long>(0x8000000000000000ull);
  const __m512i flip = axis == 0   ? _mm512_setr_epi64(m, 0, m, 0, m, 0, m, 0)
                       : axis == 1 ? _mm512_setr_epi64(m, m, 0, 0, m, m, 0, 0)
                                   : _mm512_setr_epi64(m, m, m, m, 0, 0, 0, 0);
  for (int d = 0; d < 3; ++d) {
    Lanes<H> masked;
    for (int k = 0; k < H; ++k) masked.r[k] = _mm512_maskz_mov_pd(mask[k], g[d].r[k]);
    const Lanes<H> term = mul(add(add(splat<H>(0.0), at_low<axis>(masked)), at_high<axis>(masked)), inv_h);
    for (int k = 0; k < H; ++k)
      grad[d].r[k] = _mm512_add_pd(
          grad[d].r[k], _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(term.r[k]), flip)));
  }
}

// Index tables of the 8×3 ↔ 3×8 transposes (two-source permutes: entries 8–15 pick the second).
struct Transpose {
  long long gather[3][2][8];   // [coordinate][stage][lane]: rows q[0..7][d] from the 24 node doubles
  long long scatter[3][2][8];  // [block][stage][lane]: the 24 node doubles from the 3 coordinate rows
};

constexpr Transpose transpose_tables() {
  Transpose t{};
  for (int d = 0; d < 3; ++d)
    for (int q = 0; q < 8; ++q) {
      // Stage 0 reads the node doubles 0–15 (two loads), stage 1 takes doubles 16–23 (third load).
      const int f = 3 * q + d;
      t.gather[d][0][q] = f < 16 ? f : 0;
      t.gather[d][1][q] = f < 16 ? q : 8 + (f - 16);
    }
  for (int b = 0; b < 3; ++b)
    for (int i = 0; i < 8; ++i) {
      // Block b holds doubles 8b..8b+7: double f is coordinate f % 3 of node f / 3. Stage 0
      // merges the x and y rows, stage 1 brings in the z row.
      const int f = 8 * b + i, q = f / 3, d = f % 3;
      t.scatter[b][0][i] = d == 0 ? q : d == 1 ? 8 + q : 0;
      t.scatter[b][1][i] = d == 2 ? 8 + q : i;
    }
  return t;
}

constexpr Transpose kTranspose = transpose_tables();

inline __m512i index_row(const long long (&row)[8]) { return _mm512_loadu_si512(row); }

// hex_corner_kernel in AVX-512 registers for H hexes at once: every operation of the portable
// loops in the same order (no FMA), so the same bits.
template <int H>
inline void hex_corner_kernels(const double (*const* p)[3], const double* inv_h, double eps2, double theta,
                               const unsigned* corners, double* const* e, double (*const* grad)[3]) {
  Lanes<H> inv_h8;
  for (int k = 0; k < H; ++k) inv_h8.r[k] = _mm512_set1_pd(inv_h[k]);
  Lanes<H> pos[3];
  for (int h = 0; h < H; ++h) {
    const double* flat = &p[h][0][0];
    const __m512d a = _mm512_loadu_pd(flat), b = _mm512_loadu_pd(flat + 8), c = _mm512_loadu_pd(flat + 16);
    for (int d = 0; d < 3; ++d) {
      const __m512d ab = _mm512_permutex2var_pd(a, index_row(kTranspose.gather[d][0]), b);
      pos[d].r[h] = _mm512_permutex2var_pd(ab, index_row(kTranspose.gather[d][1]), c);
    }
  }
  Lanes<H> j[3][3];  // [axis][coordinate]
  edge_column<0>(pos, inv_h8, j[0]);
  edge_column<1>(pos, inv_h8, j[1]);
  edge_column<2>(pos, inv_h8, j[2]);
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
  const __m512d eps2_8 = _mm512_set1_pd(eps2);
  const Lanes<H> det2 = mul(det, det);
  Lanes<H> root, chi, y;
  for (int k = 0; k < H; ++k) root.r[k] = _mm512_sqrt_pd(_mm512_add_pd(eps2_8, det2.r[k]));
  const Lanes<H> positive = mul(splat<H>(0.5), add(det, root));
  const __m512d half_eps2 = _mm512_mul_pd(_mm512_set1_pd(0.5), eps2_8);
  for (int k = 0; k < H; ++k) {
    chi.r[k] = barrier_chi8(det.r[k], root.r[k], positive.r[k], half_eps2);
    y.r[k] = inverse_cbrt_guess8(chi.r[k]);
  }
  const Lanes<H> four = splat<H>(4.0), third = splat<H>(1.0 / 3.0);
  for (int step = 0; step < 4; ++step) y = mul(mul(y, sub(four, mul(chi, mul(mul(y, y), y)))), third);
  const Lanes<H> inv_chi23 = mul(y, y), inv_chi = mul(inv_chi23, y);
  const Lanes<H> det2p1 = add(det2, splat<H>(1.0));
  const Lanes<H> energy = add(mul(mul(splat<H>(shape), tr), inv_chi23), mul(mul(splat<H>(theta), det2p1), inv_chi));
  for (int h = 0; h < H; ++h) _mm512_storeu_pd(e[h], energy.r[h]);
  if (!grad) return;
  cofactor_column(1);
  cofactor_column(2);
  const Lanes<H> dchi = div(chi, root);
  const Lanes<H> ja = mul(splat<H>(2.0 * shape), inv_chi23);
  const Lanes<H> first = mul(mul(mul(mul(mul(splat<H>(-(2.0 / 3.0)), splat<H>(shape)), tr), inv_chi23), inv_chi), dchi);
  const Lanes<H> second =
      mul(splat<H>(theta), sub(mul(mul(splat<H>(2.0), det), inv_chi), mul(mul(mul(det2p1, dchi), inv_chi), inv_chi)));
  const Lanes<H> jb = add(first, second);
  __mmask8 mask[H];
  for (int h = 0; h < H; ++h) mask[h] = static_cast<__mmask8>(corners[h] & 0xFFu);
  Lanes<H> g[3][3];
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d < 3; ++d) g[a][d] = add(mul(ja, j[a][d]), mul(jb, cof[a][d]));
  Lanes<H> node[3] = {splat<H>(0.0), splat<H>(0.0), splat<H>(0.0)};
  scatter_edges<0>(g[0], mask, inv_h8, node);
  scatter_edges<1>(g[1], mask, inv_h8, node);
  scatter_edges<2>(g[2], mask, inv_h8, node);
  for (int h = 0; h < H; ++h) {
    double* flat = &grad[h][0][0];
    for (int b = 0; b < 3; ++b) {
      const __m512d xy = _mm512_permutex2var_pd(node[0].r[h], index_row(kTranspose.scatter[b][0]), node[1].r[h]);
      _mm512_storeu_pd(flat + 8 * b, _mm512_permutex2var_pd(xy, index_row(kTranspose.scatter[b][1]), node[2].r[h]));
    }
  }
}

}  // namespace

void hex_corner_kernel_avx512(const double (*p)[3], double inv_h, double eps2, double theta, unsigned corners,
                              double* e, double (*grad)[3]) {
  hex_corner_kernels<1>(&p, &inv_h, eps2, theta, &corners, &e, grad ? &grad : nullptr);
}

void hex_corner_kernel2_avx512(const double (*const p[2])[3], const double inv_h[2], double eps2, double theta,
                               const unsigned corners[2], double* const e[2], double (*const grad[2])[3]) {
  hex_corner_kernels<2>(p, inv_h, eps2, theta, corners, e, grad && grad[0] ? grad : nullptr);
}
#endif

}  // namespace volspline::param::detail
