// SPDX-License-Identifier: MIT
#pragma once

namespace volspline::cli {

/// Tunes glibc's malloc for the jobs' pattern of large short-lived buffers (lattices of
/// Jacobians, Gram blocks, L-BFGS vectors of a few MB, allocated and freed many times): freed
/// memory stays in the heap instead of going back to the kernel, and a heap reserve is marked
/// for transparent huge pages, so a buffer is not page-faulted in again 4 KiB at a time for
/// every use. On the 2-core VM of the notes page faults were 20 % of mesh2spline's time on
/// bunny_closed (66k faults; 1.7k after). Results do not change (allocation only). A no-op
/// without glibc or under a sanitizer (its own allocator).
void tune_heap();

}  // namespace volspline::cli
