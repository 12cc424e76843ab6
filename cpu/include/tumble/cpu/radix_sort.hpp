// SPDX-License-Identifier: MIT
/// @file radix_sort.hpp
/// Parallel stable LSD radix sort on oneTBB with the contract of CUB `DeviceRadixSort::SortPairs`
/// / `SortKeys`: same argument order, same two-phase temp-storage protocol, same stability.
///
/// Design notes (why the output is bitwise identical for any thread count):
/// - The input is cut into fixed blocks of detail::kRadixBlockSize elements. The cut depends only
///   on n, never on the number of threads, and every block writes only its own histogram row and
///   its own output positions, so TBB's work stealing cannot change any result.
/// - One pass = per-block digit histogram -> exclusive scan in digit-major order over
///   (digit, block) -> per-block scatter in input order. Scanning digit-major makes block b's
///   keys with digit d land after those of blocks < b, and the in-order scatter keeps ties in
///   input order inside a block; together each pass is stable, so the sort is stable
///   (the classic LSD argument: Knuth, TAOCP vol. 3, 5.2.5).
/// - The first histogram pass also ORs (key ^ key[0]) into a "varying bits" mask. Slices with
///   no varying bit are skipped (high bits of cell keys are usually all zero), and the remaining
///   significant range is re-cut into evenly wide digits of at most detail::kRadixDigitBits.
///   After that the number of executed passes is known exactly, so the first executed pass
///   can pick its destination such that the last one lands in keysOut/valuesOut: ping-pong
///   without a final copy.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <immintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "tumble/hd.hpp"

namespace tumble::cpu {
namespace detail {

/// Widest digit, in bits. 11 bits won over 8 bits on 300k..4M uint64 keys with 41 significant
/// bits (bench/primitives_bench.cpp): four passes instead of six, and the 2048-bucket scatter
/// still fits L1/L2 on the 2-core development machine.
inline constexpr int kRadixDigitBits = 11;
/// Elements per block. Fixed, so the partition (and thus every intermediate) does not depend on
/// the thread count.
inline constexpr std::size_t kRadixBlockSize = std::size_t{1} << 14;
/// Alignment of every sub-buffer carved out of temp.
inline constexpr std::size_t kTempAlign = 64;

constexpr std::size_t alignUp(std::size_t bytes) noexcept {
  return (bytes + (kTempAlign - 1)) & ~(kTempAlign - 1);
}

inline void* alignPtr(void* p) noexcept {
  const auto addr = reinterpret_cast<std::uintptr_t>(p);
  return reinterpret_cast<void*>((addr + (kTempAlign - 1)) & ~std::uintptr_t{kTempAlign - 1});
}

inline int g_expWC = 0;  // EXPERIMENT
/// Placeholder value type for the keys-only sort.
struct NoValue {};

/// Sub-buffer offsets inside temp (relative to the 64-byte aligned base).
struct RadixTempLayout {
  std::size_t numBlocks = 0;
  std::size_t keysAlt = 0;    ///< n keys (ping-pong partner of keysOut)
  std::size_t valuesAlt = 0;  ///< n values (ping-pong partner of valuesOut)
  std::size_t hist = 0;       ///< numBlocks * 2^digitBits offsets
  std::size_t totals = 0;     ///< 2^digitBits digit totals, then 2^digitBits digit bases
  std::size_t masks = 0;      ///< numBlocks varying-bit masks
  std::size_t bytes = 0;      ///< total, including slack for aligning the caller's pointer
};

template <int kDigitBits, class K, class V>
constexpr RadixTempLayout radixTempLayout(std::size_t n) noexcept {
  constexpr std::size_t kRadix = std::size_t{1} << kDigitBits;
  constexpr bool kHasValues = !std::is_same_v<V, NoValue>;
  RadixTempLayout l;
  l.numBlocks = (n + kRadixBlockSize - 1) / kRadixBlockSize;
  std::size_t at = 0;
  l.keysAlt = at;
  at += alignUp(n * sizeof(K));
  l.valuesAlt = at;
  if constexpr (kHasValues) at += alignUp(n * sizeof(V));
  l.hist = at;
  at += alignUp(l.numBlocks * kRadix * sizeof(std::size_t));
  l.totals = at;
  at += alignUp(2 * kRadix * sizeof(std::size_t));
  l.masks = at;
  at += alignUp(l.numBlocks * sizeof(K));
  l.bytes = at + kTempAlign;  // the caller's pointer may be unaligned
  return l;
}

/// One digit slice [shift, shift + bits).
struct DigitSlice {
  int shift = 0;
  int bits = 0;
};

template <class K>
constexpr K bitRangeMask(int beginBit, int endBit) noexcept {
  constexpr int kKeyBits = int(sizeof(K) * 8);
  if (endBit <= beginBit) return K{0};
  const K upper = endBit >= kKeyBits ? ~K{0} : K((K{1} << endBit) - 1);
  const K lower = K((K{1} << beginBit) - 1);
  return K(upper & ~lower);
}

template <class K>
constexpr int highestBit(K x) noexcept {  // x != 0
  int b = 0;
  while (x >>= 1) ++b;
  return b;
}

template <class K>
constexpr int lowestBit(K x) noexcept {  // x != 0
  int b = 0;
  while (!(x & K{1})) {
    x >>= 1;
    ++b;
  }
  return b;
}

template <int kDigitBits, class K, class V>
class RadixSorter {
  static constexpr std::size_t kMaxRadix = std::size_t{1} << kDigitBits;
  static constexpr bool kHasValues = !std::is_same_v<V, NoValue>;
  static constexpr std::size_t kDigitGrain = 64;  // digits per task in the column scan

 public:
  RadixSorter(const RadixTempLayout& layout, void* temp, std::size_t n)
      : m_n(n), m_numBlocks(layout.numBlocks) {
    auto* base = static_cast<unsigned char*>(alignPtr(temp));
    m_keysAlt = reinterpret_cast<K*>(base + layout.keysAlt);
    m_valuesAlt = reinterpret_cast<V*>(base + layout.valuesAlt);
    m_hist = reinterpret_cast<std::size_t*>(base + layout.hist);
    m_totals = reinterpret_cast<std::size_t*>(base + layout.totals);
    m_masks = reinterpret_cast<K*>(base + layout.masks);
  }

  void sort(const K* keysIn, K* keysOut, const V* valuesIn, V* valuesOut, int beginBit,
            int endBit) {
    const K rangeMask = bitRangeMask<K>(beginBit, endBit);
    // First slice: the lowest kDigitBits of the range. Its histogram pass also finds the bits
    // that vary at all, which decides every later pass.
    const DigitSlice first{beginBit, std::min(kDigitBits, endBit - beginBit)};
    histogram(keysIn, first, /*withMask=*/true, keysIn[0]);
    K varying = 0;
    for (std::size_t b = 0; b < m_numBlocks; ++b) varying |= m_masks[b];
    varying &= rangeMask;
    if (varying == 0) {  // all keys equal on [beginBit, endBit): the stable order is the input
      copyAll(keysIn, keysOut, valuesIn, valuesOut);
      return;
    }
    const K firstMask = bitRangeMask<K>(first.shift, first.shift + first.bits);
    const bool firstRuns = (varying & firstMask) != 0;

    // Re-cut the rest of the varying range into evenly wide digits, skipping empty slices.
    DigitSlice slices[sizeof(K) * 8];
    int numSlices = 0;
    const int restBegin = std::max(first.shift + first.bits, lowestBit(varying));
    const int restEnd = highestBit(varying) + 1;
    if (restEnd > restBegin) {
      const int restBits = restEnd - restBegin;
      const int numRest = (restBits + kDigitBits - 1) / kDigitBits;
      int shift = restBegin;
      for (int i = 0; i < numRest; ++i) {
        const int bits = restBits / numRest + (i < restBits % numRest ? 1 : 0);
        if ((varying & bitRangeMask<K>(shift, shift + bits)) != 0) slices[numSlices++] = {shift, bits};
        shift += bits;
      }
    }
    const int numPasses = (firstRuns ? 1 : 0) + numSlices;

    // Pass p writes to keysOut when (numPasses - 1 - p) is even, so the last pass lands there.
    const K* srcKeys = keysIn;
    const V* srcValues = valuesIn;
    int pass = 0;
    auto runPass = [&](const DigitSlice& s) {
      const bool toOut = ((numPasses - 1 - pass) % 2) == 0;
      K* dstKeys = toOut ? keysOut : m_keysAlt;
      V* dstValues = toOut ? valuesOut : m_valuesAlt;
      scanColumns(s.bits);
      if (g_expWC == 1) scatterBuffered(srcKeys, dstKeys, srcValues, dstValues, s);
      else if (g_expWC == 2) scatterPrefetch(srcKeys, dstKeys, srcValues, dstValues, s);
      else if (g_expWC == 3) scatterNT(srcKeys, dstKeys, srcValues, dstValues, s);
      else scatter(srcKeys, dstKeys, srcValues, dstValues, s);
      srcKeys = dstKeys;
      srcValues = dstValues;
      ++pass;
    };
    if (firstRuns) runPass(first);
    for (int i = 0; i < numSlices; ++i) {
      histogram(srcKeys, slices[i], /*withMask=*/false, K{0});
      runPass(slices[i]);
    }
  }

  void copyAll(const K* keysIn, K* keysOut, const V* valuesIn, V* valuesOut) const {
    tbb::parallel_for(std::size_t{0}, m_numBlocks, [&](std::size_t b) {
      const std::size_t begin = b * kRadixBlockSize;
      const std::size_t count = std::min(kRadixBlockSize, m_n - begin);
      std::memcpy(keysOut + begin, keysIn + begin, count * sizeof(K));
      if constexpr (kHasValues) std::memcpy(valuesOut + begin, valuesIn + begin, count * sizeof(V));
    });
  }

 private:
  /// Per-block digit counts into m_hist (row b, 2^bits columns). With withMask, also the OR of
  /// (key ^ ref) per block into m_masks.
  void histogram(const K* keys, DigitSlice s, bool withMask, K ref) {
    const std::size_t radix = std::size_t{1} << s.bits;
    const K digitMask = K(radix - 1);
    tbb::parallel_for(std::size_t{0}, m_numBlocks, [&](std::size_t b) {
      const std::size_t begin = b * kRadixBlockSize;
      const std::size_t end = std::min(begin + kRadixBlockSize, m_n);
      // Two interleaved sub-histograms break the store-to-load dependency on runs of equal
      // digits (clustered keys).
      std::uint32_t counts[2][kMaxRadix];
      std::memset(counts[0], 0, radix * sizeof(std::uint32_t));
      std::memset(counts[1], 0, radix * sizeof(std::uint32_t));
      K acc = 0;
      std::size_t i = begin;
      if (withMask) {
        for (; i + 1 < end; i += 2) {
          const K k0 = keys[i];
          const K k1 = keys[i + 1];
          acc |= (k0 ^ ref) | (k1 ^ ref);
          ++counts[0][std::size_t((k0 >> s.shift) & digitMask)];
          ++counts[1][std::size_t((k1 >> s.shift) & digitMask)];
        }
        if (i < end) {
          acc |= keys[i] ^ ref;
          ++counts[0][std::size_t((keys[i] >> s.shift) & digitMask)];
        }
        m_masks[b] = acc;
      } else {
        for (; i + 1 < end; i += 2) {
          ++counts[0][std::size_t((keys[i] >> s.shift) & digitMask)];
          ++counts[1][std::size_t((keys[i + 1] >> s.shift) & digitMask)];
        }
        if (i < end) ++counts[0][std::size_t((keys[i] >> s.shift) & digitMask)];
      }
      std::size_t* row = m_hist + b * radix;
      for (std::size_t d = 0; d < radix; ++d) row[d] = std::size_t{counts[0][d]} + counts[1][d];
    });
  }

  /// Exclusive scan of m_hist in digit-major order over (digit, block): afterwards row b,
  /// column d holds the first output position of block b's keys with digit d.
  void scanColumns(int bits) {
    const std::size_t radix = std::size_t{1} << bits;
    std::size_t* totals = m_totals;
    std::size_t* bases = m_totals + kMaxRadix;
    const std::size_t numBlocks = m_numBlocks;
    std::size_t* hist = m_hist;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, radix, kDigitGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t d = r.begin(); d != r.end(); ++d) totals[d] = 0;
                        for (std::size_t b = 0; b < numBlocks; ++b) {
                          const std::size_t* row = hist + b * radix;
                          for (std::size_t d = r.begin(); d != r.end(); ++d) totals[d] += row[d];
                        }
                      });
    std::size_t running = 0;
    for (std::size_t d = 0; d < radix; ++d) {
      bases[d] = running;
      running += totals[d];
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, radix, kDigitGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t b = 0; b < numBlocks; ++b) {
                          std::size_t* row = hist + b * radix;
                          for (std::size_t d = r.begin(); d != r.end(); ++d) {
                            const std::size_t count = row[d];
                            row[d] = bases[d];
                            bases[d] += count;
                          }
                        }
                      });
  }

  /// Stable scatter of every block, in input order, to the positions from scanColumns.
  void scatter(const K* srcKeys, K* dstKeys, const V* srcValues, V* dstValues, DigitSlice s) {
    const std::size_t radix = std::size_t{1} << s.bits;
    const K digitMask = K(radix - 1);
    tbb::parallel_for(std::size_t{0}, m_numBlocks, [&](std::size_t b) {
      const std::size_t begin = b * kRadixBlockSize;
      const std::size_t end = std::min(begin + kRadixBlockSize, m_n);
      std::size_t* next = m_hist + b * radix;  // this block's row; only this task touches it
      for (std::size_t i = begin; i < end; ++i) {
        const K k = srcKeys[i];
        const std::size_t pos = next[std::size_t((k >> s.shift) & digitMask)]++;
        dstKeys[pos] = k;
        if constexpr (kHasValues) dstValues[pos] = srcValues[i];
      }
    });
  }

  static constexpr std::size_t kLine = 64 / sizeof(K);
  void scatterBuffered(const K* srcKeys, K* dstKeys, const V* srcValues, V* dstValues, DigitSlice s) {
    const std::size_t radix = std::size_t{1} << s.bits;
    const K digitMask = K(radix - 1);
    tbb::parallel_for(std::size_t{0}, m_numBlocks, [&](std::size_t b) {
      const std::size_t begin = b * kRadixBlockSize;
      const std::size_t end = std::min(begin + kRadixBlockSize, m_n);
      std::size_t* next = m_hist + b * radix;
      alignas(64) K bufK[kMaxRadix * kLine];
      alignas(64) V bufV[kHasValues ? kMaxRadix * kLine : 1];
      std::size_t origin[kMaxRadix];
      std::memcpy(origin, next, radix * sizeof(std::size_t));
      auto flush = [&](std::size_t d, std::size_t lo, std::size_t hi) {
        const std::size_t so = lo & (kLine - 1);
        std::memcpy(dstKeys + lo, bufK + d * kLine + so, (hi - lo) * sizeof(K));
        if constexpr (kHasValues) std::memcpy(dstValues + lo, bufV + d * kLine + so, (hi - lo) * sizeof(V));
      };
      for (std::size_t i = begin; i < end; ++i) {
        const K k = srcKeys[i];
        const std::size_t d = std::size_t((k >> s.shift) & digitMask);
        const std::size_t pos = next[d]++;
        const std::size_t slot = pos & (kLine - 1);
        bufK[d * kLine + slot] = k;
        if constexpr (kHasValues) bufV[d * kLine + slot] = srcValues[i];
        if (slot == kLine - 1) {
          const std::size_t lineStart = pos + 1 - kLine;
          if (lineStart >= origin[d]) {
            std::memcpy(dstKeys + lineStart, bufK + d * kLine, kLine * sizeof(K));
            if constexpr (kHasValues) std::memcpy(dstValues + lineStart, bufV + d * kLine, kLine * sizeof(V));
          } else {
            flush(d, origin[d], pos + 1);
          }
        }
      }
      for (std::size_t d = 0; d < radix; ++d) {
        const std::size_t p = next[d];
        const std::size_t lo = std::max(p & ~(kLine - 1), origin[d]);
        if (p > lo) flush(d, lo, p);
      }
    });
  }

  void scatterPrefetch(const K* srcKeys, K* dstKeys, const V* srcValues, V* dstValues, DigitSlice s) {
    const std::size_t radix = std::size_t{1} << s.bits;
    const K digitMask = K(radix - 1);
    tbb::parallel_for(std::size_t{0}, m_numBlocks, [&](std::size_t b) {
      const std::size_t begin = b * kRadixBlockSize;
      const std::size_t end = std::min(begin + kRadixBlockSize, m_n);
      std::size_t* next = m_hist + b * radix;
      for (std::size_t i = begin; i < end; ++i) {
        const K k = srcKeys[i];
        const std::size_t pos = next[std::size_t((k >> s.shift) & digitMask)]++;
        __builtin_prefetch(dstKeys + pos + 2 * kLine, 1);
        dstKeys[pos] = k;
        if constexpr (kHasValues) { __builtin_prefetch(dstValues + pos + 2 * kLine, 1); dstValues[pos] = srcValues[i]; }
      }
    });
  }

  static constexpr std::size_t kKL = 64 / sizeof(K);
  static constexpr std::size_t kVL = kHasValues ? 64 / sizeof(V) : 1;
  void scatterNT(const K* srcKeys, K* dstKeys, const V* srcValues, V* dstValues, DigitSlice s) {
    const std::size_t radix = std::size_t{1} << s.bits;
    const K digitMask = K(radix - 1);
    const std::size_t kOff = (reinterpret_cast<std::uintptr_t>(dstKeys) / sizeof(K)) & (kKL - 1);
    const std::size_t vOff = kHasValues ? (reinterpret_cast<std::uintptr_t>(dstValues) / sizeof(V)) & (kVL - 1) : 0;
    tbb::parallel_for(std::size_t{0}, m_numBlocks, [&](std::size_t b) {
      const std::size_t begin = b * kRadixBlockSize;
      const std::size_t end = std::min(begin + kRadixBlockSize, m_n);
      std::size_t* next = m_hist + b * radix;
      alignas(64) K bufK[kMaxRadix * kKL];
      alignas(64) V bufV[kHasValues ? kMaxRadix * kVL : 1];
      std::size_t origin[kMaxRadix];
      std::memcpy(origin, next, radix * sizeof(std::size_t));
      for (std::size_t i = begin; i < end; ++i) {
        const K k = srcKeys[i];
        const std::size_t d = std::size_t((k >> s.shift) & digitMask);
        const std::size_t pos = next[d]++;
        const std::size_t ks = (pos + kOff) & (kKL - 1);
        bufK[d * kKL + ks] = k;
        if (ks == kKL - 1) {
          const std::size_t ls = pos + 1 - kKL;
          if (pos + 1 >= origin[d] + kKL) {
            auto* dst = reinterpret_cast<__m128i*>(dstKeys + ls);
            const auto* src = reinterpret_cast<const __m128i*>(bufK + d * kKL);
            _mm_stream_si128(dst, _mm_load_si128(src));
            _mm_stream_si128(dst + 1, _mm_load_si128(src + 1));
            _mm_stream_si128(dst + 2, _mm_load_si128(src + 2));
            _mm_stream_si128(dst + 3, _mm_load_si128(src + 3));
          } else {
            const std::size_t lo = origin[d];
            std::memcpy(dstKeys + lo, bufK + d * kKL + ((lo + kOff) & (kKL - 1)), (pos + 1 - lo) * sizeof(K));
          }
        }
        if constexpr (kHasValues) {
          const std::size_t vs = (pos + vOff) & (kVL - 1);
          bufV[d * kVL + vs] = srcValues[i];
          if (vs == kVL - 1) {
            const std::size_t ls = pos + 1 - kVL;
            if (pos + 1 >= origin[d] + kVL) {
              auto* dst = reinterpret_cast<__m128i*>(dstValues + ls);
              const auto* src = reinterpret_cast<const __m128i*>(bufV + d * kVL);
              _mm_stream_si128(dst, _mm_load_si128(src));
              _mm_stream_si128(dst + 1, _mm_load_si128(src + 1));
              _mm_stream_si128(dst + 2, _mm_load_si128(src + 2));
              _mm_stream_si128(dst + 3, _mm_load_si128(src + 3));
            } else {
              const std::size_t lo = origin[d];
              std::memcpy(dstValues + lo, bufV + d * kVL + ((lo + vOff) & (kVL - 1)), (pos + 1 - lo) * sizeof(V));
            }
          }
        }
      }
      for (std::size_t d = 0; d < radix; ++d) {
        const std::size_t p = next[d];
        {
          const std::size_t ls = p - ((p + kOff) & (kKL - 1));
          const std::size_t lo = std::max(ls, origin[d]);
          if (p > lo) std::memcpy(dstKeys + lo, bufK + d * kKL + ((lo + kOff) & (kKL - 1)), (p - lo) * sizeof(K));
        }
        if constexpr (kHasValues) {
          const std::size_t ls = p - ((p + vOff) & (kVL - 1));
          const std::size_t lo = std::max(ls, origin[d]);
          if (p > lo) std::memcpy(dstValues + lo, bufV + d * kVL + ((lo + vOff) & (kVL - 1)), (p - lo) * sizeof(V));
        }
      }
      _mm_sfence();
    });
  }

  std::size_t m_n;
  std::size_t m_numBlocks;
  K* m_keysAlt;
  V* m_valuesAlt;
  std::size_t* m_hist;
  std::size_t* m_totals;
  K* m_masks;
};

template <int kDigitBits, class K, class V>
void radixSort(void* temp, std::size_t& tempBytes, const K* keysIn, K* keysOut, const V* valuesIn,
               V* valuesOut, std::size_t n, int beginBit, int endBit) {
  static_assert(std::is_integral_v<K> && std::is_unsigned_v<K> && !std::is_same_v<K, bool>,
                "radix sort keys must be unsigned integers");
  static_assert(std::is_trivially_copyable_v<V>, "radix sort values must be trivially copyable");
  static_assert(kDigitBits >= 1 && kDigitBits <= 16, "digit width out of range");
  constexpr bool kHasValues = !std::is_same_v<V, NoValue>;
  const RadixTempLayout layout = radixTempLayout<kDigitBits, K, V>(n);
  if (temp == nullptr) {
    tempBytes = layout.bytes;
    return;
  }
  TUMBLE_ASSERT(tempBytes >= layout.bytes, "radix sort: temp storage too small");
  TUMBLE_ASSERT(0 <= beginBit && beginBit <= endBit && endBit <= int(sizeof(K) * 8),
                "radix sort: need 0 <= beginBit <= endBit <= key bits");
  TUMBLE_ASSERT(n == 0 || keysIn != keysOut, "radix sort: keysOut must not alias keysIn");
  if (n == 0) return;
  RadixSorter<kDigitBits, K, V> sorter(layout, temp, n);
  if (n == 1 || beginBit >= endBit) {
    sorter.copyAll(keysIn, keysOut, valuesIn, valuesOut);
    return;
  }
  if constexpr (kHasValues) {
    TUMBLE_ASSERT(static_cast<const void*>(valuesIn) != static_cast<const void*>(valuesOut),
                  "radix sort: valuesOut must not alias valuesIn");
  }
  sorter.sort(keysIn, keysOut, valuesIn, valuesOut, beginBit, endBit);
}

}  // namespace detail

/// Sorts (key, value) pairs by key, stably, looking only at key bits [beginBit, endBit).
/// Same argument order and two-phase protocol as CUB `DeviceRadixSort::SortPairs`.
///
/// - Two phases: with `temp == nullptr` the call only writes the required size to `tempBytes`
///   and returns. That size depends only on `n`, `K` and `V` (never on the thread count or on
///   the bit range), so one allocation per capacity is enough. Then call again with `temp`
///   pointing to at least `tempBytes` bytes (any alignment; sub-buffers are aligned to 64).
/// - Preconditions: `K` is an unsigned integer; `V` is trivially copyable;
///   `0 <= beginBit <= endBit <= 8 * sizeof(K)`; `keysIn`/`valuesIn` hold `n` elements,
///   `keysOut`/`valuesOut` have room for `n`.
/// - Aliasing: `keysIn` and `valuesIn` are read only and left unchanged. The four arrays and
///   `temp` must not overlap one another (in particular, not in place).
/// - Stability: pairs whose keys are equal on the sorted bits keep their input order, exactly as
///   CUB's "DeviceRadixSort is stable". Bits outside the range are carried along but ignored.
/// - Extra memory: `temp` ≈ n keys + n values + ceil(n / 16384) * 2^11 offsets (about 8n + 8 KiB
///   of histograms per 16K elements for uint64 keys and uint32 values) + a few KiB. Nothing is
///   allocated inside the call.
/// - Work: one read of the keys for the first digit histogram, then per executed 11-bit digit one
///   more read for the histogram and one scattered copy. Digits in which no key differs are
///   skipped (e.g. high bits that are zero in every key).
/// - Thread safety: runs tbb::parallel_for in the calling arena and honours
///   tbb::global_control. Concurrent calls are safe if they use distinct `temp` and outputs.
/// - Determinism: a stable sort has exactly one correct output, and every intermediate is
///   computed on fixed blocks independent of the thread count, so the results are bitwise
///   identical for any thread count and any run (CCCL terms: `gpu_to_gpu`), and equal to CUB's.
/// - `n == 0` does nothing; `n == 1` and `beginBit == endBit` copy the input.
template <class K, class V>
void radixSortPairs(void* temp, std::size_t& tempBytes, const K* keysIn, K* keysOut,
                    const V* valuesIn, V* valuesOut, std::size_t n, int beginBit = 0,
                    int endBit = int(sizeof(K) * 8)) {
  detail::radixSort<detail::kRadixDigitBits, K, V>(temp, tempBytes, keysIn, keysOut, valuesIn,
                                                   valuesOut, n, beginBit, endBit);
}

/// Sorts keys, looking only at bits [beginBit, endBit). Same contract as radixSortPairs without
/// the values (CUB `DeviceRadixSort::SortKeys`): two-phase `temp`, `keysIn` unchanged and not
/// overlapping `keysOut` or `temp`, stable (keys equal on the sorted bits keep their input
/// order, which is visible when bits outside the range differ), extra memory ≈ n keys plus
/// histograms, bitwise identical output for any thread count.
template <class K>
void radixSortKeys(void* temp, std::size_t& tempBytes, const K* keysIn, K* keysOut,
                   std::size_t n, int beginBit = 0, int endBit = int(sizeof(K) * 8)) {
  detail::radixSort<detail::kRadixDigitBits, K, detail::NoValue>(
      temp, tempBytes, keysIn, keysOut, static_cast<const detail::NoValue*>(nullptr),
      static_cast<detail::NoValue*>(nullptr), n, beginBit, endBit);
}

}  // namespace tumble::cpu
