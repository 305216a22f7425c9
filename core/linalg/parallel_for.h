// SPDX-License-Identifier: MIT
#pragma once

#include <functional>

namespace volspline::linalg {

/// Threads a job uses when its options leave the count automatic: the hardware's concurrency,
/// at least 1 and at most 8 (beyond that the memory-bound fits gain little).
int default_thread_count();

/// Runs body(chunk) for every chunk in [0, num_chunks), spread over up to `threads` threads
/// (the calling thread is one of them); returns when all chunks are done. Chunks are taken in
/// increasing order but may run in any order and concurrently, so a body writes only data that
/// its chunk owns: with a chunk count that does not depend on `threads` and results combined in
/// chunk order afterwards, the output is the same for every thread count. threads ≤ 1 or
/// num_chunks ≤ 1 runs every chunk inline in order and never creates a thread (the WebAssembly
/// build has none; there every call runs inline). If bodies throw, the exception of the lowest
/// throwing chunk is rethrown once the others have finished (chunks above a throwing one may be
/// skipped, chunks below it always run).
void parallel_for(int threads, int num_chunks, const std::function<void(int chunk)>& body);

}  // namespace volspline::linalg
