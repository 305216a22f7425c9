// SPDX-License-Identifier: MIT
#include "cli/heap_tuning.h"

#include <cstddef>

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
#define VOLSPLINE_OWN_ALLOCATOR 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define VOLSPLINE_OWN_ALLOCATOR 1
#endif

#if defined(__GLIBC__) && defined(__linux__) && !defined(VOLSPLINE_OWN_ALLOCATOR)
#include <malloc.h>
#define VOLSPLINE_TUNE_GLIBC 1
#endif

namespace volspline::cli {

void tune_heap() {
#ifdef VOLSPLINE_TUNE_GLIBC
  constexpr std::size_t kMiB = std::size_t(1) << 20;
  // Blocks up to 32 MiB (glibc's largest threshold) come from the heap, not from mmap (which
  // unmaps on free), and the heap is never trimmed.
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(32 * kMiB));
  mallopt(M_TRIM_THRESHOLD, static_cast<int>(1024 * kMiB));
#endif
}

}  // namespace volspline::cli
