// SPDX-License-Identifier: MIT
// Internal: the row sweeps of NodeJacobians built for AVX2 (node_jacobians_avx2.cpp). No
// includes: that file is compiled with -mavx2, and nothing inline may come from a header there.
#pragma once

namespace volspline::spline::detail {

#if defined(VOLSPLINE_AVX2_KERNELS)
/// m = Σ_e x_{column[e]}·g_eᵀ over entries begin .. end − 1 (g_e: gradient[3e .. 3e + 2]); x4:
/// 4 doubles per column; m: 9 doubles, column-major. The bits of NodeJacobians::linear's loop.
void node_rows_linear_avx2(const int* column, const float* gradient, int begin, int end, const double* x4,
                           double* m);
/// gradient4[4·column[e] ..] += d·g_e over entries begin .. end − 1 (d: 9 doubles, column-major).
/// The bits of NodeJacobians::add_gradient's loop.
void node_rows_add_gradient_avx2(const int* column, const float* gradient, int begin, int end, const double* d,
                                 double* gradient4);
/// node_rows_linear_avx2 with gradients in double precision: the bits of scattered_linear's loop.
void scattered_linear_avx2(const int* column, const double* gradient, int begin, int end, const double* x4,
                           double* m);
#endif

}  // namespace volspline::spline::detail
