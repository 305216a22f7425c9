// SPDX-License-Identifier: MIT
#include "core/linalg/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

// The WebAssembly build is compiled without -pthread: no thread may be created there.
#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
#define VOLSPLINE_NO_THREADS 1
#endif

namespace volspline::linalg {

int default_thread_count() {
#ifdef VOLSPLINE_NO_THREADS
  return 1;
#else
  const unsigned hardware = std::thread::hardware_concurrency();
  return std::clamp(static_cast<int>(hardware), 1, 8);
#endif
}

void parallel_for(int threads, int num_chunks, const std::function<void(int chunk)>& body) {
  if (num_chunks <= 0) return;
#ifdef VOLSPLINE_NO_THREADS
  (void)threads;
  for (int c = 0; c < num_chunks; ++c) body(c);
#else
  if (threads <= 1 || num_chunks == 1) {
    for (int c = 0; c < num_chunks; ++c) body(c);
    return;
  }
  std::atomic<int> next{0};
  // Lowest chunk that threw so far: chunks above it are skipped, chunks below it still run, so
  // the exception rethrown is that of the lowest throwing chunk whatever the scheduling.
  std::atomic<int> error_chunk{num_chunks};
  std::mutex error_mutex;
  std::exception_ptr error;
  auto work = [&]() {
    for (;;) {
      const int c = next.fetch_add(1);
      if (c >= num_chunks) return;
      if (c > error_chunk.load()) continue;
      try {
        body(c);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (c < error_chunk.load()) {
          error_chunk = c;
          error = std::current_exception();
        }
      }
    }
  };
  const int helpers = std::min(threads, num_chunks) - 1;
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(helpers));
  for (int t = 0; t < helpers; ++t) {
    try {
      pool.emplace_back(work);
    } catch (const std::system_error&) {
      break;  // no more threads available: the ones running (at least this one) do all chunks
    }
  }
  work();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
#endif
}

}  // namespace volspline::linalg
