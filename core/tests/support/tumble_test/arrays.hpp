// SPDX-License-Identifier: MIT
// Helpers shared by the primitive tests: array comparison and the CUB-style size list.
#pragma once
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <type_traits>
#include <vector>

namespace tumble::cpu::test {

/// Bitwise comparison of two arrays, naming the first mismatch.
template <class T>
::testing::AssertionResult sameArray(const std::vector<T>& actual, const std::vector<T>& expected) {
  if (actual.size() != expected.size())
    return ::testing::AssertionFailure() << "size " << actual.size() << " != " << expected.size();
  for (std::size_t i = 0; i < actual.size(); ++i) {
    if (std::memcmp(&actual[i], &expected[i], sizeof(T)) != 0) {
      auto failure = ::testing::AssertionFailure() << "first mismatch at index " << i;
      if constexpr (std::is_integral_v<T>) failure << ": got " << +actual[i] << ", expected " << +expected[i];
      return failure;
    }
  }
  return ::testing::AssertionSuccess();
}

/// Sizes at tile and block boundaries (as CUB's tests pick them) plus four random sizes below
/// maxRandom drawn from `seed`.
inline std::vector<std::size_t> testSizes(std::uint64_t seed, std::size_t maxRandom) {
  std::vector<std::size_t> sizes = {0,    1,    2,     31,    32,    33,    127,   128,
                                    129,  1023, 1024,  1025,  16383, 16384, 16385, 32767,
                                    32768, 32769};
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 4; ++i) sizes.push_back(2 + rng() % maxRandom);
  return sizes;
}

/// Runs f with TBB limited to `threads` worker threads (global limit and an arena of that size).
template <class F>
void withThreads(int threads, F&& f) {
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  tbb::task_arena arena(threads);
  arena.execute(f);
}

}  // namespace tumble::cpu::test
