// SPDX-License-Identifier: MIT
// foldover_kernel<4> compiled with -mavx2 (and without FMA: the lanes keep the scalar bits).
#include "core/param/foldover_kernel.h"

namespace volspline::param::detail {

#if defined(VOLSPLINE_AVX2_KERNELS)
void foldover_kernel4_avx2(const double* j, double eps, double theta, double* energy, double* gradient) {
  foldover_kernel<4>(j, eps, theta, energy, gradient);
}
#endif

}  // namespace volspline::param::detail
