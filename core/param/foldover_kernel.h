// SPDX-License-Identifier: MIT
// Internal: the element energy of foldover_free_energy for L elements at once, written as
// loops over lanes so that a compiler vectorizes them (foldover_batch_avx2.cpp builds it for
// AVX2) while every lane does the same operations in the same order as the scalar build: no
// FMA, no reassociation, so every build gives the same bits (native SSE2, native AVX2, wasm).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace volspline::param::detail {

// Internal linkage: every translation unit keeps its own copy, compiled with its own flags. As
// inline functions of external linkage the -mavx2 copy of foldover_batch_avx2.cpp and the
// baseline copy would be one symbol, and the linker would keep one of them for both: the "AVX2"
// kernel running SSE2 code, or the baseline path running AVX2 code on CPUs without it.
namespace {

// cbrt(y) for normal y > 0 in IEEE operations only (libm's cbrt differs between machines and
// builds; this is the same everywhere): Kahan's exponent-third guess (≈5 %), then three Halley
// steps r ← r − r·(r³ − y)/(2r³ + y) (cubic convergence; a fourth changes nothing): within 3 ulp
// of libm's cbrt, enough for an energy.
inline double cbrt_positive(double y) {
  y = y < 2.2250738585072014e-308 ? 2.2250738585072014e-308 : y;  // normal (the guess reads the exponent)
  std::uint64_t bits;
  std::memcpy(&bits, &y, sizeof bits);
  const std::uint32_t high = static_cast<std::uint32_t>(bits >> 32);
  const std::uint64_t guess_high = static_cast<std::uint64_t>(high) * 0xAAAAAAABull >> 33;  // high / 3
  const std::uint64_t guess_bits = (guess_high + 715094163ull) << 32;
  double r;
  std::memcpy(&r, &guess_bits, sizeof r);
  for (int step = 0; step < 3; ++step) {
    const double r3 = r * r * r;
    r = r - r * ((r3 - y) / (2.0 * r3 + y));
  }
  return r;
}

// j[k·L + l]: entry k (column-major 3×3) of element l. energy[l]; gradient (if not null) like j.
template <int L>
inline void foldover_kernel(const double* j, double eps, double theta, double* energy, double* gradient) {
  double d[L], root[L], x_d[L], tr[L], x23[L];
  auto at = [&](int row, int col, int l) { return j[(row + 3 * col) * L + l]; };
  for (int l = 0; l < L; ++l) {
    d[l] = at(0, 0, l) * (at(1, 1, l) * at(2, 2, l) - at(2, 1, l) * at(1, 2, l)) -
           at(0, 1, l) * (at(1, 0, l) * at(2, 2, l) - at(2, 0, l) * at(1, 2, l)) +
           at(0, 2, l) * (at(1, 0, l) * at(2, 1, l) - at(2, 0, l) * at(1, 1, l));
    root[l] = std::sqrt(eps * eps + d[l] * d[l]);
    x_d[l] = 0.5 * (d[l] + root[l]);
    double s = 0.0;
    for (int k = 0; k < 9; ++k) s += j[k * L + l] * j[k * L + l];
    tr[l] = s;
  }
  for (int l = 0; l < L; ++l) x23[l] = cbrt_positive(x_d[l] * x_d[l]);
  for (int l = 0; l < L; ++l)
    energy[l] = (1.0 - theta) * tr[l] / x23[l] + theta * (d[l] * d[l] + 1.0) / x_d[l];
  if (!gradient) return;
  for (int l = 0; l < L; ++l) {
    const double dchi = 0.5 * (1.0 + d[l] / root[l]);
    const double a = (1.0 - theta) * 2.0 / x23[l];
    const double b = -(1.0 - theta) * (2.0 / 3.0) * tr[l] / (x23[l] * x_d[l]) * dchi +
                     theta * (2.0 * d[l] / x_d[l] - (d[l] * d[l] + 1.0) * dchi / (x_d[l] * x_d[l]));
    // ∂f/∂J = a·J + b·cof(J), cof = ∂ det J/∂J (columns: cross products of the other two).
    for (int col = 0; col < 3; ++col) {
      const int c1 = (col + 1) % 3, c2 = (col + 2) % 3;
      for (int row = 0; row < 3; ++row) {
        const int r1 = (row + 1) % 3, r2 = (row + 2) % 3;
        const double cof = at(r1, c1, l) * at(r2, c2, l) - at(r2, c1, l) * at(r1, c2, l);
        gradient[(row + 3 * col) * L + l] = a * at(row, col, l) + b * cof;
      }
    }
  }
}

}  // namespace

#if defined(VOLSPLINE_AVX2_KERNELS)
/// foldover_kernel<4> built for AVX2 (foldover_batch_avx2.cpp).
void foldover_kernel4_avx2(const double* j, double eps, double theta, double* energy, double* gradient);
#endif

}  // namespace volspline::param::detail
