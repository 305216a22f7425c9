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

// The start of x^(−1/3) for normal x > 0 without division or libm: the exponent divided by 3 as
// an integer (≤ 4 % off); hex_corner_kernel then takes 4 Newton steps y ← y(4 − x y³)/3 on
// y⁻³ = x, quadratic (4 % → 1e-16, a few ulps).
inline double inverse_cbrt_guess(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits = 0x553edc82c19c9000ULL - bits / 3;
  double y;
  std::memcpy(&y, &bits, sizeof y);
  return y;
}

// The energy of foldover_kernel (Garanzha et al. 2021) at the 8 corner tetrahedra of one hex,
// lane c = corner c: p[q] is node q (offset (q&1, q>>1&1, q>>2&1)), corner c's J has column
// a = the +axis hex edge through c, times inv_h. e[c] gets the energy of every corner; if grad
// is not null, grad[q] gets the gradient over the nodes of the corners flagged in `corners`
// (bit c). All 8 lanes are computed the same way, so that a compiler can vectorize them; no FMA
// and no reassociation, so every build gives the same bits.
inline void hex_corner_kernel(const double (*p)[3], double inv_h, double eps2, double theta, unsigned corners,
                              double* e, double (*grad)[3]) {
  double edge[3][8][3];  // [axis][lower corner][coordinate]
  for (int a = 0; a < 3; ++a)
    for (int q = 0; q < 8; ++q) {
      if (q & (1 << a)) continue;
      for (int d = 0; d < 3; ++d) edge[a][q][d] = (p[q | (1 << a)][d] - p[q][d]) * inv_h;
    }
  // j[a][d][c]: coordinate d of J's column a at corner c.
  double j[3][3][8];
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d < 3; ++d)
      for (int c = 0; c < 8; ++c) j[a][d][c] = edge[a][c & ~(1 << a)][d];
  const double shape = 1.0 - theta;
  double cof[3][3][8], det[8], tr[8], root[8], chi[8], inv_cbrt[8];
  // Column a of cof(J): the cross product of the other two columns (column 0 gives det J; the
  // others only the gradient).
  auto cofactor_column = [&](int a) {
    const double(*u)[8] = j[(a + 1) % 3];
    const double(*v)[8] = j[(a + 2) % 3];
    for (int d = 0; d < 3; ++d)
      for (int c = 0; c < 8; ++c)
        cof[a][d][c] = u[(d + 1) % 3][c] * v[(d + 2) % 3][c] - u[(d + 2) % 3][c] * v[(d + 1) % 3][c];
  };
  cofactor_column(0);
  for (int c = 0; c < 8; ++c) {
    det[c] = j[0][0][c] * cof[0][0][c] + j[0][1][c] * cof[0][1][c] + j[0][2][c] * cof[0][2][c];
    double t = 0.0;
    for (int a = 0; a < 3; ++a) t += j[a][0][c] * j[a][0][c] + j[a][1][c] * j[a][1][c] + j[a][2][c] * j[a][2][c];
    tr[c] = t;
    root[c] = std::sqrt(eps2 + det[c] * det[c]);
    // χ = (D + √(ε² + D²))/2, in the cancellation-free form for D < 0.
    const double positive = 0.5 * (det[c] + root[c]), negative = 0.5 * eps2 / (root[c] - det[c]);
    chi[c] = det[c] >= 0.0 ? positive : negative;
  }
  for (int c = 0; c < 8; ++c) inv_cbrt[c] = inverse_cbrt_guess(chi[c]);
  for (int step = 0; step < 4; ++step)
    for (int c = 0; c < 8; ++c)
      inv_cbrt[c] = inv_cbrt[c] * (4.0 - chi[c] * (inv_cbrt[c] * inv_cbrt[c] * inv_cbrt[c])) * (1.0 / 3.0);
  for (int c = 0; c < 8; ++c) {
    const double inv_chi23 = inv_cbrt[c] * inv_cbrt[c], inv_chi = inv_chi23 * inv_cbrt[c];
    e[c] = shape * tr[c] * inv_chi23 + theta * (det[c] * det[c] + 1.0) * inv_chi;
  }
  if (!grad) return;
  cofactor_column(1);
  cofactor_column(2);
  double ja[8], jb[8];
  for (int c = 0; c < 8; ++c) {
    const double inv_chi23 = inv_cbrt[c] * inv_cbrt[c], inv_chi = inv_chi23 * inv_cbrt[c];
    // ∂f/∂J = ja·J + jb·cof(J), ∂χ/∂D = (1 + D/√(ε² + D²))/2.
    const double dchi = chi[c] / root[c];
    ja[c] = 2.0 * shape * inv_chi23;
    jb[c] = -(2.0 / 3.0) * shape * tr[c] * inv_chi23 * inv_chi * dchi +
            theta * (2.0 * det[c] * inv_chi - (det[c] * det[c] + 1.0) * dchi * inv_chi * inv_chi);
  }
  double g[3][3][8];
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d < 3; ++d)
      for (int c = 0; c < 8; ++c) g[a][d][c] = ja[c] * j[a][d][c] + jb[c] * cof[a][d][c];
  double edge_grad[3][8][3] = {};
  for (int c = 0; c < 8; ++c) {
    if (!(corners & (1u << c))) continue;
    for (int a = 0; a < 3; ++a) {
      double* eg = edge_grad[a][c & ~(1 << a)];
      for (int d = 0; d < 3; ++d) eg[d] += g[a][d][c];
    }
  }
  for (int q = 0; q < 8; ++q) grad[q][0] = grad[q][1] = grad[q][2] = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int q = 0; q < 8; ++q) {
      if (q & (1 << a)) continue;
      for (int d = 0; d < 3; ++d) {
        const double edge_term = edge_grad[a][q][d] * inv_h;
        grad[q | (1 << a)][d] += edge_term;
        grad[q][d] -= edge_term;
      }
    }
}

}  // namespace

/// hex_corner_kernel, run in AVX-512 or AVX2 registers where the CPU has them (the same bits):
/// the entry point of the hex untanglers (barrier_untangling.cpp).
void hex_corner_terms(const double (*p)[3], double inv_h, double eps2, double theta, unsigned corners, double* e,
                      double (*grad)[3]);

/// hex_corner_terms for two hexes (hex h: p[h], inv_h[h], corners[h], e[h], grad[h]; grad or
/// grad[0] null: energies only), the same bits as two calls.
void hex_corner_terms2(const double (*const p[2])[3], const double inv_h[2], double eps2, double theta,
                       const unsigned corners[2], double* const e[2], double (*const grad[2])[3]);

#if defined(VOLSPLINE_AVX2_KERNELS)
/// hex_corner_kernel in AVX2 registers (foldover_batch_avx2.cpp).
void hex_corner_kernel_avx2(const double (*p)[3], double inv_h, double eps2, double theta, unsigned corners,
                            double* e, double (*grad)[3]);
/// hex_corner_kernel_avx2 for two hexes at once (hex h: p[h], inv_h[h], corners[h], e[h],
/// grad[h]; grad or grad[0] null: energies only), the same bits as two calls: the two hexes' chains
/// overlap in the core.
void hex_corner_kernel2_avx2(const double (*const p[2])[3], const double inv_h[2], double eps2, double theta,
                             const unsigned corners[2], double* const e[2], double (*const grad[2])[3]);
/// foldover_kernel<4> built for AVX2 (foldover_batch_avx2.cpp).
void foldover_kernel4_avx2(const double* j, double eps, double theta, double* energy, double* gradient);
#endif

#if defined(VOLSPLINE_AVX512_KERNELS)
/// hex_corner_kernel in AVX-512 registers, a hex's 8 corners in one (foldover_batch_avx512.cpp).
void hex_corner_kernel_avx512(const double (*p)[3], double inv_h, double eps2, double theta, unsigned corners,
                              double* e, double (*grad)[3]);
/// hex_corner_kernel_avx512 for two hexes at once, as hex_corner_kernel2_avx2.
void hex_corner_kernel2_avx512(const double (*const p[2])[3], const double inv_h[2], double eps2, double theta,
                               const unsigned corners[2], double* const e[2], double (*const grad[2])[3]);
#endif

}  // namespace volspline::param::detail
