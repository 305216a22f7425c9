// SPDX-License-Identifier: MIT
#include "cli/heap_tuning.h"

#include <cstdint>

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
#include <sys/mman.h>
#include <unistd.h>
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
  // A 256 MiB heap reserve (address space only: pages are made on first touch, 2 MiB at a time
  // in the huge-page range), grown with blocks under the threshold and given back to malloc.
  constexpr int kBlocks = 8;
  constexpr std::size_t kBlock = 32 * kMiB - 64 * 1024;
  void* start = sbrk(0);
  void* blocks[kBlocks] = {};
  for (void*& b : blocks) b = malloc(kBlock);
  void* end = sbrk(0);
  const std::uintptr_t huge = 2 * kMiB;
  const std::uintptr_t lo = (reinterpret_cast<std::uintptr_t>(start) + huge - 1) & ~(huge - 1);
  const std::uintptr_t hi = reinterpret_cast<std::uintptr_t>(end) & ~(huge - 1);
  if (start != reinterpret_cast<void*>(-1) && end != reinterpret_cast<void*>(-1) && hi > lo)
    madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);  // advice: failure is harmless
  for (void* b : blocks) free(b);
#endif
}

}  // namespace volspline::cli
