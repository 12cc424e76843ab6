// SPDX-License-Identifier: MIT
// tumble::cpu::radixSortPairs / radixSortKeys against std::stable_sort on the masked bits.
// Values are the input indices, so comparing values checks stability, not only sortedness.
// Sizes follow CUB's tile-boundary picks plus our own block boundaries (16K); every random
// case logs its seed via SCOPED_TRACE.
#include "tumble/cpu/radix_sort.hpp"

#include <gtest/gtest.h>

#include "tumble_test/arrays.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace {

using tumble::cpu::test::sameArray;

using tumble::cpu::radixSortKeys;
using tumble::cpu::radixSortPairs;

// LowBits: 41 significant bits for uint64 (as cell keys), 20 for uint32.
// Skewed: 99% of the keys below 2^20, the rest spread over the LowBits range (one huge MSD
// bucket that still needs sorting). Geometric: random magnitudes (MSD buckets of every size,
// from empty through insertion-sorted to huge).
enum class Dist { Uniform, LowBits, FewDistinct, AllEqual, SparseBits, Clustered, Skewed, Geometric };

const char* toString(Dist d) {
  switch (d) {
    case Dist::Uniform: return "uniform";
    case Dist::LowBits: return "lowBits";
    case Dist::FewDistinct: return "fewDistinct";
    case Dist::AllEqual: return "allEqual";
    case Dist::SparseBits: return "sparseBits";
    case Dist::Clustered: return "clustered";
    case Dist::Skewed: return "skewed";
    case Dist::Geometric: return "geometric";
  }
  return "?";
}

constexpr Dist kAllDists[] = {Dist::Uniform,    Dist::LowBits,   Dist::FewDistinct,
                              Dist::AllEqual,   Dist::SparseBits, Dist::Clustered,
                              Dist::Skewed,     Dist::Geometric};

std::uint64_t caseSeed(std::size_t n, Dist d, int salt) {
  return 0x9E3779B97F4A7C15ull ^ (std::uint64_t(n) * 0x100000001B3ull) ^
         (std::uint64_t(d) << 48) ^ (std::uint64_t(salt) << 56);
}

template <class K>
constexpr K maskBits(int beginBit, int endBit) {
  constexpr int kBits = int(sizeof(K) * 8);
  if (endBit <= beginBit) return 0;
  const K upper = endBit >= kBits ? ~K{0} : K((K{1} << endBit) - 1);
  return K(upper & ~K((K{1} << beginBit) - 1));
}

template <class K>
std::vector<K> makeKeys(Dist d, std::size_t n, std::uint64_t seed) {
  constexpr int kBits = int(sizeof(K) * 8);
  std::mt19937_64 rng(seed);
  std::vector<K> keys(n);
  const int sigBits = kBits == 64 ? 41 : 20;
  K distinct[4];
  for (K& k : distinct) k = K(rng());
  const K base = K(rng()) & maskBits<K>(0, sigBits);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t r = rng();
    switch (d) {
      case Dist::Uniform: keys[i] = K(r); break;
      case Dist::LowBits: keys[i] = K(r) & maskBits<K>(0, sigBits); break;
      case Dist::FewDistinct: keys[i] = distinct[r % 4]; break;
      case Dist::AllEqual: keys[i] = distinct[0]; break;
      // Only bits 0, 1 and kBits-3 vary: the slices in between must be skipped.
      case Dist::SparseBits: keys[i] = K(distinct[0] & ~K(K{3} | (K{1} << (kBits - 3)))) |
                                       K(r & 3) | K(((r >> 8) & 1) << (kBits - 3)); break;
      // Dense cluster around one key: long runs of equal high digits.
      case Dist::Clustered: keys[i] = K(base + (r & 0x3FF)); break;
      case Dist::Skewed:
        keys[i] = (r >> 32) % 100 == 0 ? K(r & maskBits<K>(0, sigBits)) : K(r & 0xFFFFF);
        break;
      case Dist::Geometric: keys[i] = K(K(r & maskBits<K>(0, sigBits)) >> ((r >> 48) % sigBits)); break;
    }
  }
  return keys;
}

/// Stable reference permutation: indices sorted by key bits [beginBit, endBit).
template <class K>
std::vector<std::uint32_t> referencePermutation(const std::vector<K>& keys, int beginBit, int endBit) {
  std::vector<std::uint32_t> perm(keys.size());
  std::iota(perm.begin(), perm.end(), 0u);
  const K mask = maskBits<K>(beginBit, endBit);
  std::stable_sort(perm.begin(), perm.end(), [&](std::uint32_t a, std::uint32_t b) {
    return (keys[a] & mask) < (keys[b] & mask);
  });
  return perm;
}


/// Runs radixSortPairs with an unaligned, garbage-filled temp and returns the outputs.
template <class K, class V>
void runPairs(const std::vector<K>& keys, const std::vector<V>& values, std::vector<K>& outKeys,
              std::vector<V>& outValues, int beginBit, int endBit) {
  const std::size_t n = keys.size();
  std::size_t tempBytes = 0;
  radixSortPairs<K, V>(nullptr, tempBytes, keys.data(), nullptr, values.data(), nullptr, n,
                       beginBit, endBit);
  ASSERT_GT(tempBytes, 0u);
  std::vector<unsigned char> temp(tempBytes + 1, 0xAB);
  outKeys.assign(n, K(0x5A5A5A5A));
  outValues.assign(n, V{});
  radixSortPairs<K, V>(temp.data() + 1, tempBytes, keys.data(), outKeys.data(), values.data(),
                       outValues.data(), n, beginBit, endBit);
}

template <class K>
void checkPairs(const std::vector<K>& keys, int beginBit, int endBit) {
  SCOPED_TRACE("bits [" + std::to_string(beginBit) + ", " + std::to_string(endBit) + ")");
  const std::size_t n = keys.size();
  std::vector<std::uint32_t> values(n);
  std::iota(values.begin(), values.end(), 0u);
  const std::vector<K> keysCopy = keys;
  const std::vector<std::uint32_t> valuesCopy = values;

  const std::vector<std::uint32_t> perm = referencePermutation(keys, beginBit, endBit);
  std::vector<K> expectedKeys(n);
  for (std::size_t i = 0; i < n; ++i) expectedKeys[i] = keys[perm[i]];

  std::vector<K> outKeys;
  std::vector<std::uint32_t> outValues;
  runPairs(keys, values, outKeys, outValues, beginBit, endBit);
  EXPECT_TRUE(sameArray(outKeys, expectedKeys)) << "keys";
  EXPECT_TRUE(sameArray(outValues, perm)) << "values (stability)";
  EXPECT_TRUE(sameArray(keys, keysCopy)) << "keysIn modified";
  EXPECT_TRUE(sameArray(values, valuesCopy)) << "valuesIn modified";
}

template <class K>
void checkKeys(const std::vector<K>& keys, int beginBit, int endBit) {
  SCOPED_TRACE("keys only, bits [" + std::to_string(beginBit) + ", " + std::to_string(endBit) + ")");
  const std::size_t n = keys.size();
  const std::vector<std::uint32_t> perm = referencePermutation(keys, beginBit, endBit);
  std::vector<K> expected(n);
  for (std::size_t i = 0; i < n; ++i) expected[i] = keys[perm[i]];
  std::size_t tempBytes = 0;
  radixSortKeys<K>(nullptr, tempBytes, keys.data(), nullptr, n, beginBit, endBit);
  std::vector<unsigned char> temp(tempBytes, 0xCD);
  std::vector<K> out(n, K(0x5A));
  radixSortKeys<K>(temp.data(), tempBytes, keys.data(), out.data(), n, beginBit, endBit);
  EXPECT_TRUE(sameArray(out, expected));
}

std::vector<std::size_t> testSizes() { return tumble::cpu::test::testSizes(20240611, 200000); }  // seed fixes the random sizes

template <class K>
std::vector<std::pair<int, int>> bitRanges() {
  if constexpr (sizeof(K) == 8)
    return {{0, 64}, {0, 20}, {8, 40}, {0, 41}, {63, 64}, {13, 13}};
  else
    return {{0, 32}, {4, 12}, {0, 20}, {31, 32}, {7, 7}};
}

template <class K>
class RadixSortTest : public ::testing::Test {};
using KeyTypes = ::testing::Types<std::uint32_t, std::uint64_t>;
TYPED_TEST_SUITE(RadixSortTest, KeyTypes);

TYPED_TEST(RadixSortTest, MatchesStableSortFullRange) {
  using K = TypeParam;
  for (const std::size_t n : testSizes()) {
    for (const Dist d : kAllDists) {
      const std::uint64_t seed = caseSeed(n, d, 1);
      SCOPED_TRACE("n=" + std::to_string(n) + " dist=" + toString(d) + " seed=" + std::to_string(seed));
      checkPairs(makeKeys<K>(d, n, seed), 0, int(sizeof(K) * 8));
    }
  }
}

TYPED_TEST(RadixSortTest, MatchesStableSortPartialBits) {
  using K = TypeParam;
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{33}, std::size_t{1025},
                              std::size_t{16385}, std::size_t{70001}}) {
    for (const Dist d : kAllDists) {
      const std::uint64_t seed = caseSeed(n, d, 2);
      SCOPED_TRACE("n=" + std::to_string(n) + " dist=" + toString(d) + " seed=" + std::to_string(seed));
      const std::vector<K> keys = makeKeys<K>(d, n, seed);
      for (const auto& [b, e] : bitRanges<K>()) checkPairs(keys, b, e);
    }
  }
}

TYPED_TEST(RadixSortTest, KeysOnlyMatchesStableSort) {
  using K = TypeParam;
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{129},
                              std::size_t{16384}, std::size_t{50000}}) {
    for (const Dist d : kAllDists) {
      const std::uint64_t seed = caseSeed(n, d, 3);
      SCOPED_TRACE("n=" + std::to_string(n) + " dist=" + toString(d) + " seed=" + std::to_string(seed));
      const std::vector<K> keys = makeKeys<K>(d, n, seed);
      for (const auto& [b, e] : bitRanges<K>()) checkKeys(keys, b, e);
    }
  }
}

TYPED_TEST(RadixSortTest, LargeInput) {
  using K = TypeParam;
  const std::size_t n = 3'000'000;
  for (const Dist d : {Dist::LowBits, Dist::FewDistinct, Dist::Skewed}) {
    const std::uint64_t seed = caseSeed(n, d, 4);
    SCOPED_TRACE("n=" + std::to_string(n) + " dist=" + toString(d) + " seed=" + std::to_string(seed));
    const std::vector<K> keys = makeKeys<K>(d, n, seed);
    checkPairs(keys, 0, int(sizeof(K) * 8));
  }
}

// Sizes around and above detail::kRadixHybridMinN (MSD split into in-cache buckets), with the
// bit ranges that cell keys use.
TYPED_TEST(RadixSortTest, HybridSizes) {
  using K = TypeParam;
  constexpr int kSig = sizeof(K) == 8 ? 41 : 20;
  for (const std::size_t n : {std::size_t{131071}, std::size_t{131072}, std::size_t{300001},
                              std::size_t{400000}}) {
    for (const Dist d : kAllDists) {
      const std::uint64_t seed = caseSeed(n, d, 6);
      SCOPED_TRACE("n=" + std::to_string(n) + " dist=" + toString(d) + " seed=" + std::to_string(seed));
      const std::vector<K> keys = makeKeys<K>(d, n, seed);
      checkPairs(keys, 0, int(sizeof(K) * 8));
      checkPairs(keys, 0, kSig);
      checkPairs(keys, 3, kSig - 5);
      if (n == 300001) checkKeys(keys, 0, kSig);
    }
  }
}

struct Payload {  // a wider trivially copyable value
  std::uint32_t id;
  float weight;
  double extra;
};

TEST(RadixSortPairs, StructValues) {
  const std::size_t n = 40000;
  const std::uint64_t seed = 77;
  SCOPED_TRACE("seed=" + std::to_string(seed));
  const std::vector<std::uint64_t> keys = makeKeys<std::uint64_t>(Dist::FewDistinct, n, seed);
  std::vector<Payload> values(n);
  for (std::size_t i = 0; i < n; ++i) values[i] = {std::uint32_t(i), float(i) * 0.5f, double(i) + 0.25};
  std::vector<std::uint64_t> outKeys;
  std::vector<Payload> outValues;
  runPairs(keys, values, outKeys, outValues, 0, 64);
  const std::vector<std::uint32_t> perm = referencePermutation(keys, 0, 64);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(outKeys[i], keys[perm[i]]) << "at " << i;
    ASSERT_EQ(std::memcmp(&outValues[i], &values[perm[i]], sizeof(Payload)), 0) << "at " << i;
  }
}

TEST(RadixSortPairs, EqualKeysOutsideRangeKeepInputOrder) {
  // Keys differ only above endBit: nothing to sort, so the output must be the input, in order.
  const std::size_t n = 20000;
  std::vector<std::uint64_t> keys(n);
  for (std::size_t i = 0; i < n; ++i) keys[i] = (std::uint64_t(n - i) << 40) | 0x123;
  checkPairs(keys, 0, 40);
  checkPairs(keys, 5, 5);
}

TEST(RadixSortPairs, TempBytesIndependentOfThreadsAndBits) {
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{1000}, std::size_t{300000},
                              std::size_t{2'000'000}}) {
    SCOPED_TRACE("n=" + std::to_string(n));
    std::size_t reference = 0;
    radixSortPairs<std::uint64_t, std::uint32_t>(nullptr, reference, nullptr, nullptr, nullptr,
                                                 nullptr, n);
    EXPECT_GT(reference, 0u);
    for (const int threads : {1, 2, 3}) {
      tumble::cpu::test::withThreads(threads, [&] {
        std::size_t bytes = 0;
        radixSortPairs<std::uint64_t, std::uint32_t>(nullptr, bytes, nullptr, nullptr, nullptr,
                                                     nullptr, n, 3, 47);
        EXPECT_EQ(bytes, reference) << "threads=" << threads;
      });
    }
  }
}

TEST(RadixSortPairs, BitwiseIdenticalForAnyThreadCount) {
  for (const std::size_t n : {std::size_t{1025}, std::size_t{100000}, std::size_t{300000}}) {
    for (const Dist d : {Dist::LowBits, Dist::FewDistinct, Dist::Clustered, Dist::Skewed, Dist::Geometric}) {
      const std::uint64_t seed = caseSeed(n, d, 5);
      SCOPED_TRACE("n=" + std::to_string(n) + " dist=" + toString(d) + " seed=" + std::to_string(seed));
      const std::vector<std::uint64_t> keys = makeKeys<std::uint64_t>(d, n, seed);
      std::vector<std::uint32_t> values(n);
      std::iota(values.begin(), values.end(), 0u);
      std::vector<std::uint64_t> firstKeys;
      std::vector<std::uint32_t> firstValues;
      for (const int threads : {1, 2, 3}) {
        SCOPED_TRACE("threads=" + std::to_string(threads));
        std::vector<std::uint64_t> outKeys;
        std::vector<std::uint32_t> outValues;
        tumble::cpu::test::withThreads(threads, [&] { runPairs(keys, values, outKeys, outValues, 0, 41); });
        if (threads == 1) {
          firstKeys = outKeys;
          firstValues = outValues;
          constexpr std::uint64_t kMask = maskBits<std::uint64_t>(0, 41);
          EXPECT_TRUE(std::is_sorted(outKeys.begin(), outKeys.end(), [](std::uint64_t a, std::uint64_t b) {
            return (a & kMask) < (b & kMask);
          }));
        } else {
          EXPECT_TRUE(sameArray(outKeys, firstKeys));
          EXPECT_TRUE(sameArray(outValues, firstValues));
        }
      }
    }
  }
}

}  // namespace
