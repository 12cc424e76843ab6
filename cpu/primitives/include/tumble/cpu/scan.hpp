// SPDX-License-Identifier: MIT
/// @file scan.hpp
/// Parallel prefix sums on oneTBB with the contract of CUB `DeviceScan::ExclusiveSum` /
/// `InclusiveSum`: same argument order and two-phase temp-storage protocol.
///
/// Design note: reduce-then-scan over fixed blocks of detail::kScanBlockSize elements
/// (1. per-block sums in parallel, 2. serial exclusive scan of the block sums, 3. per-block
/// scan seeded with the block's offset, in parallel). The block cut depends only on n, and
/// integer addition is exactly associative, so the output is bitwise identical for any thread
/// count. Sums are formed in the unsigned type of the same width, so overflow wraps modulo
/// 2^bits for signed T too (as two's complement on the GPU) instead of being undefined.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include <tbb/parallel_for.h>

#include "tumble/hd.hpp"

namespace tumble::cpu {
namespace detail {

/// Elements per scan block: fixed, so the partition does not depend on the thread count.
inline constexpr std::size_t kScanBlockSize = std::size_t{1} << 14;

template <class T>
constexpr std::size_t scanTempBytes(std::size_t n) noexcept {
  const std::size_t numBlocks = std::max<std::size_t>(1, (n + kScanBlockSize - 1) / kScanBlockSize);
  return ((numBlocks * sizeof(T) + 63) & ~std::size_t{63}) + 64;
}

template <bool kInclusive, class T>
void prefixSum(void* temp, std::size_t& tempBytes, const T* in, T* out, std::size_t n) {
  static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>,
                "scan: T must be an integer type (float sums are not reproducible)");
  using U = std::make_unsigned_t<T>;
  const std::size_t required = scanTempBytes<T>(n);
  if (temp == nullptr) {
    tempBytes = required;
    return;
  }
  TUMBLE_ASSERT(tempBytes >= required, "scan: temp storage too small");
  TUMBLE_ASSERT(in == out ||
                    reinterpret_cast<std::uintptr_t>(out + n) <= reinterpret_cast<std::uintptr_t>(in) ||
                    reinterpret_cast<std::uintptr_t>(in + n) <= reinterpret_cast<std::uintptr_t>(out),
                "scan: in and out must be identical or disjoint");
  if (n == 0) return;
  const auto addr = reinterpret_cast<std::uintptr_t>(temp);
  U* blockSums = reinterpret_cast<U*>((addr + 63) & ~std::uintptr_t{63});
  const std::size_t numBlocks = (n + kScanBlockSize - 1) / kScanBlockSize;

  // Scans one block seeded with `running`. Reads in[i] before writing out[i], so in == out works.
  auto scanBlock = [in, out, n](std::size_t b, U running) {
    const std::size_t begin = b * kScanBlockSize;
    const std::size_t end = std::min(begin + kScanBlockSize, n);
    for (std::size_t i = begin; i < end; ++i) {
      const U v = static_cast<U>(in[i]);
      if constexpr (kInclusive) {
        running = U(running + v);
        out[i] = static_cast<T>(running);
      } else {
        out[i] = static_cast<T>(running);
        running = U(running + v);
      }
    }
  };
  if (numBlocks == 1) {
    scanBlock(0, U{0});
    return;
  }
  tbb::parallel_for(std::size_t{0}, numBlocks, [&](std::size_t b) {
    const std::size_t begin = b * kScanBlockSize;
    const std::size_t end = std::min(begin + kScanBlockSize, n);
    U sum = 0;
    for (std::size_t i = begin; i < end; ++i) sum = U(sum + static_cast<U>(in[i]));
    blockSums[b] = sum;
  });
  U running = 0;
  for (std::size_t b = 0; b < numBlocks; ++b) {
    const U sum = blockSums[b];
    blockSums[b] = running;
    running = U(running + sum);
  }
  tbb::parallel_for(std::size_t{0}, numBlocks,
                    [&](std::size_t b) { scanBlock(b, blockSums[b]); });
}

}  // namespace detail

/// Exclusive prefix sum: out[0] = 0, out[i] = in[0] + ... + in[i-1].
/// Same argument order and two-phase protocol as CUB `DeviceScan::ExclusiveSum`.
///
/// - Two phases: with `temp == nullptr` only writes the required size to `tempBytes` (it depends
///   only on `n` and `T`, never on the thread count; always > 0). Then call again with `temp`
///   pointing to at least `tempBytes` bytes (any alignment).
/// - Preconditions: `T` is an integer type (floats are rejected at compile time: their sums
///   depend on the association order). Sums wrap modulo 2^(8*sizeof(T)), also for signed T.
/// - Aliasing: **in place is allowed** (`in == out`). Otherwise `in` and `out` must not overlap,
///   and neither may overlap `temp`.
/// - Extra memory: one T per 16384 elements plus 128 bytes. Nothing is allocated.
/// - Thread safety: runs tbb::parallel_for in the calling arena and honours
///   tbb::global_control. Concurrent calls are safe with distinct `temp` and outputs.
/// - Determinism: integer addition is associative and blocks are fixed, so the output is
///   bitwise identical for any thread count (CCCL terms: `gpu_to_gpu`) and equal to CUB's.
template <class T>
void exclusiveSum(void* temp, std::size_t& tempBytes, const T* in, T* out, std::size_t n) {
  detail::prefixSum<false>(temp, tempBytes, in, out, n);
}

/// Inclusive prefix sum: out[i] = in[0] + ... + in[i]. Same contract as exclusiveSum (CUB
/// `DeviceScan::InclusiveSum`): two-phase `temp`, integer T only, in place allowed, bitwise
/// identical for any thread count.
template <class T>
void inclusiveSum(void* temp, std::size_t& tempBytes, const T* in, T* out, std::size_t n) {
  detail::prefixSum<true>(temp, tempBytes, in, out, n);
}

}  // namespace tumble::cpu
