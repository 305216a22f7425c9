// SPDX-License-Identifier: MIT
// The Horner passes of TSpline's cell polynomials (tspline.cpp horner3, horner3_gradient) compiled
// with -mavx2 (core/CMakeLists.txt): the D components of a monomial and, for the rational form
// (Eq. 4.1), the denominator share one register, so each lane runs the scalar products and sums
// in their order, without FMA, and gives the same bits. Plain pointers and no header with inline
// code: an inline function compiled here with AVX2 could replace the portable copy at link time.
#include "core/spline/cell_polynomial_avx2.h"

#if defined(VOLSPLINE_AVX2_KERNELS)
#include <immintrin.h>

namespace volspline::spline::detail {

namespace {

// Monomial m's numerator components in lanes 0 .. D−1 and, with kDenominator, the denominator in
// lane D (an unaligned load reading past the D components, then a blend of the broadcast).
template <int D, bool kDenominator>
inline __m256d load_monomial(const double* numerator, const double* denominator, int m) {
  const __m256d v = _mm256_loadu_pd(numerator + m * D);
  if constexpr (kDenominator) {
    static_assert(D < 4, "no free lane for the denominator");
    return _mm256_blend_pd(v, _mm256_broadcast_sd(denominator + m), 1 << D);
  } else {
    return v;
  }
}

inline __m256d mul(__m256d x, __m256d y) { return _mm256_mul_pd(x, y); }
inline __m256d add(__m256d x, __m256d y) { return _mm256_add_pd(x, y); }

}  // namespace

template <int D, bool kDenominator>
void cell_horner_avx2(const double* numerator, const double* denominator, const double* s, double* lanes) {
  const __m256d s0 = _mm256_set1_pd(s[0]), s1 = _mm256_set1_pd(s[1]), s2 = _mm256_set1_pd(s[2]);
  __m256d out = _mm256_setzero_pd();
  for (int a = 3; a >= 0; --a) {
    __m256d acc = _mm256_setzero_pd();
    for (int b = 3; b >= 0; --b) {
      const int m = (4 * a + b) * 4;
      const __m256d q0 = load_monomial<D, kDenominator>(numerator, denominator, m);
      const __m256d q1 = load_monomial<D, kDenominator>(numerator, denominator, m + 1);
      const __m256d q2 = load_monomial<D, kDenominator>(numerator, denominator, m + 2);
      const __m256d q3 = load_monomial<D, kDenominator>(numerator, denominator, m + 3);
      const __m256d t = add(mul(add(mul(add(mul(q3, s2), q2), s2), q1), s2), q0);
      acc = add(mul(acc, s1), t);
    }
    out = add(mul(out, s0), acc);
  }
  _mm256_storeu_pd(lanes, out);
}

template <int D, bool kDenominator>
void cell_horner_gradient_avx2(const double* numerator, const double* denominator, const double* s, double* lanes) {
  const __m256d s0 = _mm256_set1_pd(s[0]), s1 = _mm256_set1_pd(s[1]), s2 = _mm256_set1_pd(s[2]);
  const __m256d two = _mm256_set1_pd(2.0), three = _mm256_set1_pd(3.0);
  __m256d t2[4], t2_1[4], t2_2[4];
  for (int a = 0; a < 4; ++a) {
    __m256d t1[4], t1_2[4];
    for (int b = 0; b < 4; ++b) {
      const int m = (4 * a + b) * 4;
      const __m256d q0 = load_monomial<D, kDenominator>(numerator, denominator, m);
      const __m256d q1 = load_monomial<D, kDenominator>(numerator, denominator, m + 1);
      const __m256d q2 = load_monomial<D, kDenominator>(numerator, denominator, m + 2);
      const __m256d q3 = load_monomial<D, kDenominator>(numerator, denominator, m + 3);
      t1[b] = add(mul(add(mul(add(mul(q3, s2), q2), s2), q1), s2), q0);
      t1_2[b] = add(mul(add(mul(mul(three, q3), s2), mul(two, q2)), s2), q1);
    }
    t2[a] = add(mul(add(mul(add(mul(t1[3], s1), t1[2]), s1), t1[1]), s1), t1[0]);
    t2_1[a] = add(mul(add(mul(mul(three, t1[3]), s1), mul(two, t1[2])), s1), t1[1]);
    t2_2[a] = add(mul(add(mul(add(mul(t1_2[3], s1), t1_2[2]), s1), t1_2[1]), s1), t1_2[0]);
  }
  _mm256_storeu_pd(lanes, add(mul(add(mul(add(mul(t2[3], s0), t2[2]), s0), t2[1]), s0), t2[0]));
  _mm256_storeu_pd(lanes + 4, add(mul(add(mul(mul(three, t2[3]), s0), mul(two, t2[2])), s0), t2[1]));
  _mm256_storeu_pd(lanes + 8, add(mul(add(mul(add(mul(t2_1[3], s0), t2_1[2]), s0), t2_1[1]), s0), t2_1[0]));
  _mm256_storeu_pd(lanes + 12, add(mul(add(mul(add(mul(t2_2[3], s0), t2_2[2]), s0), t2_2[1]), s0), t2_2[0]));
}

template <int K>
void cell_horner_points_avx2(const double* coef, const double* s, double* out) {
  const __m256d s0 = _mm256_loadu_pd(s), s1 = _mm256_loadu_pd(s + 4), s2 = _mm256_loadu_pd(s + 8);
  __m256d result[K];
  for (int d = 0; d < K; ++d) result[d] = _mm256_setzero_pd();
  for (int a = 3; a >= 0; --a) {
    __m256d acc[K];
    for (int d = 0; d < K; ++d) acc[d] = _mm256_setzero_pd();
    for (int b = 3; b >= 0; --b) {
      const double* q = coef + (4 * a + b) * 4 * K;
      for (int d = 0; d < K; ++d) {
        const __m256d q0 = _mm256_broadcast_sd(q + d), q1 = _mm256_broadcast_sd(q + K + d);
        const __m256d q2 = _mm256_broadcast_sd(q + 2 * K + d), q3 = _mm256_broadcast_sd(q + 3 * K + d);
        acc[d] = add(mul(acc[d], s1), add(mul(add(mul(add(mul(q3, s2), q2), s2), q1), s2), q0));
      }
    }
    for (int d = 0; d < K; ++d) result[d] = add(mul(result[d], s0), acc[d]);
  }
  for (int d = 0; d < K; ++d) _mm256_storeu_pd(out + 4 * d, result[d]);
}

template <int K>
void cell_horner_gradient_points_avx2(const double* coef, const double* s, double* out) {
  const __m256d s0 = _mm256_loadu_pd(s), s1 = _mm256_loadu_pd(s + 4), s2 = _mm256_loadu_pd(s + 8);
  const __m256d two = _mm256_set1_pd(2.0), three = _mm256_set1_pd(3.0);
  for (int d = 0; d < K; ++d) {
    __m256d t2[4], t2_1[4], t2_2[4];
    for (int a = 0; a < 4; ++a) {
      __m256d t1[4], t1_2[4];
      for (int b = 0; b < 4; ++b) {
        const double* q = coef + (4 * a + b) * 4 * K + d;
        const __m256d q0 = _mm256_broadcast_sd(q), q1 = _mm256_broadcast_sd(q + K);
        const __m256d q2 = _mm256_broadcast_sd(q + 2 * K), q3 = _mm256_broadcast_sd(q + 3 * K);
        t1[b] = add(mul(add(mul(add(mul(q3, s2), q2), s2), q1), s2), q0);
        t1_2[b] = add(mul(add(mul(mul(three, q3), s2), mul(two, q2)), s2), q1);
      }
      t2[a] = add(mul(add(mul(add(mul(t1[3], s1), t1[2]), s1), t1[1]), s1), t1[0]);
      t2_1[a] = add(mul(add(mul(mul(three, t1[3]), s1), mul(two, t1[2])), s1), t1[1]);
      t2_2[a] = add(mul(add(mul(add(mul(t1_2[3], s1), t1_2[2]), s1), t1_2[1]), s1), t1_2[0]);
    }
    _mm256_storeu_pd(out + 4 * d, add(mul(add(mul(add(mul(t2[3], s0), t2[2]), s0), t2[1]), s0), t2[0]));
    _mm256_storeu_pd(out + 4 * (K + d), add(mul(add(mul(mul(three, t2[3]), s0), mul(two, t2[2])), s0), t2[1]));
    _mm256_storeu_pd(out + 4 * (2 * K + d),
                     add(mul(add(mul(add(mul(t2_1[3], s0), t2_1[2]), s0), t2_1[1]), s0), t2_1[0]));
    _mm256_storeu_pd(out + 4 * (3 * K + d),
                     add(mul(add(mul(add(mul(t2_2[3], s0), t2_2[2]), s0), t2_2[1]), s0), t2_2[0]));
  }
}

template void cell_horner_points_avx2<1>(const double*, const double*, double*);
template void cell_horner_points_avx2<2>(const double*, const double*, double*);
template void cell_horner_points_avx2<3>(const double*, const double*, double*);
template void cell_horner_points_avx2<4>(const double*, const double*, double*);
template void cell_horner_gradient_points_avx2<1>(const double*, const double*, double*);
template void cell_horner_gradient_points_avx2<2>(const double*, const double*, double*);
template void cell_horner_gradient_points_avx2<3>(const double*, const double*, double*);
template void cell_horner_gradient_points_avx2<4>(const double*, const double*, double*);
template void cell_horner_avx2<1, false>(const double*, const double*, const double*, double*);
template void cell_horner_avx2<2, false>(const double*, const double*, const double*, double*);
template void cell_horner_avx2<3, false>(const double*, const double*, const double*, double*);
template void cell_horner_avx2<4, false>(const double*, const double*, const double*, double*);
template void cell_horner_avx2<1, true>(const double*, const double*, const double*, double*);
template void cell_horner_avx2<2, true>(const double*, const double*, const double*, double*);
template void cell_horner_avx2<3, true>(const double*, const double*, const double*, double*);
template void cell_horner_gradient_avx2<1, false>(const double*, const double*, const double*, double*);
template void cell_horner_gradient_avx2<2, false>(const double*, const double*, const double*, double*);
template void cell_horner_gradient_avx2<3, false>(const double*, const double*, const double*, double*);
template void cell_horner_gradient_avx2<4, false>(const double*, const double*, const double*, double*);
template void cell_horner_gradient_avx2<1, true>(const double*, const double*, const double*, double*);
template void cell_horner_gradient_avx2<2, true>(const double*, const double*, const double*, double*);
template void cell_horner_gradient_avx2<3, true>(const double*, const double*, const double*, double*);

}  // namespace volspline::spline::detail
#endif
