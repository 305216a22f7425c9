// SPDX-License-Identifier: MIT
#pragma once

namespace volspline::cli {

/// Tunes glibc's malloc for the jobs' pattern of large short-lived buffers (lattices of
/// Jacobians, Gram blocks, L-BFGS vectors of a few MB, allocated and freed many times): freed
/// memory stays in the heap instead of going back to the kernel, so a buffer is not
/// page-faulted in again for every use (without this, page faults are a fifth of mesh2spline's
/// time on bunny_closed). No heap reserve in transparent huge pages: kernels that zero 2 MiB
/// pages far slower than 4 KiB ones make it cost more system time than it saves. Results do not
/// change (allocation only). A no-op without glibc or under a sanitizer (its own allocator).
void tune_heap();

}  // namespace volspline::cli
