// SPDX-License-Identifier: MIT
#pragma once

namespace volspline::cli {

/// Tunes glibc's malloc for the jobs' pattern of large short-lived buffers (lattices of
/// Jacobians, Gram blocks, L-BFGS vectors of a few MB, allocated and freed many times): freed
/// memory stays in the heap instead of going back to the kernel, so a buffer is not
/// page-faulted in again for every use. On the 2-core VM of the notes page faults were 20 % of
/// mesh2spline's time on bunny_closed. A heap reserve marked for transparent huge pages was
/// dropped: there the kernel zeroes 2 MiB pages far slower than 4 KiB ones (bunny 0.24 s
/// system time against 0.07, 2.29 against 2.11 s CPU). Results do not change (allocation
/// only). A no-op without glibc or under a sanitizer (its own allocator).
void tune_heap();

}  // namespace volspline::cli
