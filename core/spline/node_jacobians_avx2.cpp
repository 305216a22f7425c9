// SPDX-License-Identifier: MIT
// The row sweeps of NodeJacobians compiled with -mavx2 (core/CMakeLists.txt), one 4-lane register
// per column of J (lane 3 unused): the same products and sums per entry as the scalar loops of
// node_jacobians.cpp, in the same order, and no FMA, so both paths give the same bits (about
// twice as fast on bunny). Plain pointers and no header with inline code: an inline Eigen or
// standard-library function compiled here with AVX2 could replace the portable copy at link time.
#include "core/spline/node_jacobians_avx2.h"

#if defined(VOLSPLINE_AVX2_KERNELS)
#include <immintrin.h>

namespace volspline::spline::detail {

namespace {

// (p0, p1, p2, 0) and back: 128-bit and scalar moves (masked moves are slow on some CPUs).
inline __m256d load3(const double* p) {
  return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_load_sd(p + 2), 1);
}
inline void store3(double* p, __m256d v) {
  _mm_storeu_pd(p, _mm256_castpd256_pd128(v));
  _mm_store_sd(p + 2, _mm256_extractf128_pd(v, 1));
}
inline __m256d broadcast(const float* g) {
  return _mm256_cvtps_pd(_mm_broadcast_ss(g));  // exact, as double(*g)
}
inline __m256d broadcast(const double* g) { return _mm256_broadcast_sd(g); }

// m[3a .. 3a + 2] = Σ_e gradient_e[a] · x4[column_e] over rows [begin, end) (the Jacobian's linear
// part): the same products and sums in the same order for float and double gradients.
template <class Real>
void linear_part(const int* column, const Real* gradient, int begin, int end, const double* x4, double* m) {
  __m256d m0 = _mm256_setzero_pd(), m1 = _mm256_setzero_pd(), m2 = _mm256_setzero_pd();
  for (int e = begin; e < end; ++e) {
    const Real* g = gradient + 3 * e;
    const __m256d xc = _mm256_loadu_pd(x4 + 4 * column[e]);
    m0 = _mm256_add_pd(m0, _mm256_mul_pd(xc, broadcast(g)));
    m1 = _mm256_add_pd(m1, _mm256_mul_pd(xc, broadcast(g + 1)));
    m2 = _mm256_add_pd(m2, _mm256_mul_pd(xc, broadcast(g + 2)));
  }
  store3(m, m0);
  store3(m + 3, m1);
  store3(m + 6, m2);
}

}  // namespace

void node_rows_linear_avx2(const int* column, const float* gradient, int begin, int end, const double* x4,
                           double* m) {
  linear_part(column, gradient, begin, end, x4, m);
}

void scattered_linear_avx2(const int* column, const double* gradient, int begin, int end, const double* x4,
                           double* m) {
  linear_part(column, gradient, begin, end, x4, m);
}

void node_rows_add_gradient_avx2(const int* column, const float* gradient, int begin, int end, const double* d,
                                 double* gradient4) {
  const __m256d d0 = load3(d), d1 = load3(d + 3), d2 = load3(d + 6);
  for (int e = begin; e < end; ++e) {
    const float* g = gradient + 3 * e;
    double* out = gradient4 + 4 * column[e];
    const __m256d t01 = _mm256_add_pd(_mm256_mul_pd(d0, broadcast(g)), _mm256_mul_pd(d1, broadcast(g + 1)));
    const __m256d t = _mm256_add_pd(t01, _mm256_mul_pd(d2, broadcast(g + 2)));
    _mm256_storeu_pd(out, _mm256_add_pd(_mm256_loadu_pd(out), t));
  }
}

}  // namespace volspline::spline::detail
#endif
