// SPDX-License-Identifier: MIT
#include "core/linalg/parallel_for.h"

#include <doctest/doctest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace linalg = volspline::linalg;

TEST_CASE("parallel_for runs every chunk exactly once for any thread count") {
  for (int threads : {1, 2, 3, 8}) {
    for (int chunks : {0, 1, 2, 7, 100}) {
      std::vector<int> runs(static_cast<std::size_t>(chunks), 0);
      linalg::parallel_for(threads, chunks, [&](int c) { ++runs[c]; });
      for (int r : runs) CHECK(r == 1);
    }
  }
}

TEST_CASE("chunk results combined in chunk order do not depend on the thread count") {
  // Floating-point sums of chunk partial sums: the same bits for 1, 2 and 5 threads.
  std::vector<double> x(10000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = 1.0 / (1.0 + static_cast<double>(i) * 0.37);
  auto total = [&](int threads) {
    std::vector<double> partial(40, 0.0);
    linalg::parallel_for(threads, 40, [&](int c) {
      for (std::size_t i = c * 250; i < (c + 1) * 250u; ++i) partial[c] += x[i];
    });
    double sum = 0.0;
    for (double p : partial) sum += p;
    return sum;
  };
  CHECK(total(1) == total(2));
  CHECK(total(1) == total(5));
}

TEST_CASE("the exception of the lowest throwing chunk is rethrown") {
  for (int threads : {1, 2, 4}) {
    try {
      linalg::parallel_for(threads, 50, [](int c) {
        if (c == 17 || c == 33) throw std::runtime_error("chunk " + std::to_string(c));
      });
      FAIL("no exception");
    } catch (const std::runtime_error& e) {
      CHECK(std::string(e.what()) == "chunk 17");
    }
  }
}

TEST_CASE("the default thread count is within [1, 8]") {
  const int n = linalg::default_thread_count();
  CHECK(n >= 1);
  CHECK(n <= 8);
}
