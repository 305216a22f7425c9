// SPDX-License-Identifier: MIT
// foldover_kernel<4> and hex_corner_kernel compiled with -mavx2 (and without FMA: the lanes keep the scalar bits).
#include "core/param/foldover_kernel.h"

namespace volspline::param::detail {

#if defined(VOLSPLINE_AVX2_KERNELS)
void foldover_kernel4_avx2(const double* j, double eps, double theta, double* energy, double* gradient) {
  foldover_kernel<4>(j, eps, theta, energy, gradient);
}

void hex_corner_kernel_avx2(const double (*p)[3], double inv_h, double eps2, double theta, unsigned corners,
                            double* e, double (*grad)[3]) {
  hex_corner_kernel(p, inv_h, eps2, theta, corners, e, grad);
}
#endif

}  // namespace volspline::param::detail
