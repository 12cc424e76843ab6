// SPDX-License-Identifier: MIT
// tumble::cpu::exclusiveSum / inclusiveSum against std::exclusive_scan / std::inclusive_scan.
// The reference sums in the unsigned type of the same width, so wrap-around (which the contract
// defines) is compared too. Sizes follow CUB's tile-boundary picks plus our 16K block
// boundaries; every random case logs its seed via SCOPED_TRACE.
#include "tumble/cpu/scan.hpp"

#include <gtest/gtest.h>

#include "tumble_test/arrays.hpp"

#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using tumble::cpu::test::sameArray;

using tumble::cpu::exclusiveSum;
using tumble::cpu::inclusiveSum;

enum class Values { Small, Full, Zeros };

const char* toString(Values v) {
  switch (v) {
    case Values::Small: return "small";
    case Values::Full: return "full";
    case Values::Zeros: return "zeros";
  }
  return "?";
}

std::uint64_t caseSeed(std::size_t n, Values v, int salt) {
  return 0xC2B2AE3D27D4EB4Full ^ (std::uint64_t(n) * 0x9E3779B97F4A7C15ull) ^
         (std::uint64_t(v) << 40) ^ (std::uint64_t(salt) << 52);
}

template <class T>
std::vector<T> makeInput(Values v, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<T> in(n);
  for (T& x : in) {
    const std::uint64_t r = rng();
    switch (v) {
      case Values::Small: x = static_cast<T>(r % 17); break;  // counts, as pair counts are
      case Values::Full: x = static_cast<T>(static_cast<std::make_unsigned_t<T>>(r)); break;
      case Values::Zeros: x = T{0}; break;
    }
  }
  return in;
}

template <class T>
std::vector<T> reference(const std::vector<T>& in, bool inclusive) {
  using U = std::make_unsigned_t<T>;
  std::vector<U> u(in.size()), s(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) u[i] = static_cast<U>(in[i]);
  if (inclusive)
    std::inclusive_scan(u.begin(), u.end(), s.begin());
  else
    std::exclusive_scan(u.begin(), u.end(), s.begin(), U{0});
  std::vector<T> out(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) out[i] = static_cast<T>(s[i]);
  return out;
}


/// Runs the scan out of place (unaligned garbage temp) and in place; both must match.
template <class T>
void checkScan(const std::vector<T>& in, bool inclusive) {
  SCOPED_TRACE(inclusive ? "inclusive" : "exclusive");
  auto scan = [inclusive](void* temp, std::size_t& bytes, const T* src, T* dst, std::size_t n) {
    if (inclusive)
      inclusiveSum<T>(temp, bytes, src, dst, n);
    else
      exclusiveSum<T>(temp, bytes, src, dst, n);
  };
  const std::size_t n = in.size();
  const std::vector<T> expected = reference(in, inclusive);
  std::size_t tempBytes = 0;
  scan(nullptr, tempBytes, in.data(), nullptr, n);
  ASSERT_GT(tempBytes, 0u);
  std::vector<unsigned char> temp(tempBytes + 3, 0xEE);

  const std::vector<T> inCopy = in;
  std::vector<T> out(n, T(0x5A));
  scan(temp.data() + 3, tempBytes, in.data(), out.data(), n);
  EXPECT_TRUE(sameArray(out, expected)) << "out of place";
  EXPECT_TRUE(sameArray(in, inCopy)) << "input modified";

  std::vector<T> inPlace = in;
  scan(temp.data(), tempBytes, inPlace.data(), inPlace.data(), n);
  EXPECT_TRUE(sameArray(inPlace, expected)) << "in place";
}

std::vector<std::size_t> testSizes() { return tumble::cpu::test::testSizes(987654321, 300000); }  // seed fixes the random sizes

template <class T>
class ScanTest : public ::testing::Test {};
using ScanTypes = ::testing::Types<std::uint32_t, std::uint64_t, std::int32_t, std::int64_t>;
TYPED_TEST_SUITE(ScanTest, ScanTypes);

TYPED_TEST(ScanTest, MatchesStdScan) {
  using T = TypeParam;
  for (const std::size_t n : testSizes()) {
    for (const Values v : {Values::Small, Values::Full, Values::Zeros}) {
      const std::uint64_t seed = caseSeed(n, v, 1);
      SCOPED_TRACE("n=" + std::to_string(n) + " values=" + toString(v) + " seed=" + std::to_string(seed));
      const std::vector<T> in = makeInput<T>(v, n, seed);
      checkScan(in, false);
      checkScan(in, true);
    }
  }
}

TYPED_TEST(ScanTest, LargeInput) {
  using T = TypeParam;
  const std::size_t n = 3'000'000;
  const std::uint64_t seed = caseSeed(n, Values::Small, 2);
  SCOPED_TRACE("n=" + std::to_string(n) + " seed=" + std::to_string(seed));
  checkScan(makeInput<T>(Values::Small, n, seed), false);
}

TEST(Scan, TempBytesIndependentOfThreads) {
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{100000}, std::size_t{3'000'000}}) {
    SCOPED_TRACE("n=" + std::to_string(n));
    std::size_t reference = 0;
    exclusiveSum<std::uint32_t>(nullptr, reference, nullptr, nullptr, n);
    EXPECT_GT(reference, 0u);
    for (const int threads : {1, 2, 3}) {
      tumble::cpu::test::withThreads(threads, [&] {
        std::size_t bytes = 0;
        exclusiveSum<std::uint32_t>(nullptr, bytes, nullptr, nullptr, n);
        EXPECT_EQ(bytes, reference) << "threads=" << threads;
      });
    }
  }
}

TEST(Scan, BitwiseIdenticalForAnyThreadCount) {
  for (const std::size_t n : {std::size_t{1025}, std::size_t{100000}, std::size_t{1'000'000}}) {
    const std::uint64_t seed = caseSeed(n, Values::Full, 3);
    SCOPED_TRACE("n=" + std::to_string(n) + " seed=" + std::to_string(seed));
    const std::vector<std::uint32_t> in = makeInput<std::uint32_t>(Values::Full, n, seed);
    const std::vector<std::uint32_t> expected = reference(in, false);
    for (const int threads : {1, 2, 3}) {
      SCOPED_TRACE("threads=" + std::to_string(threads));
      std::vector<std::uint32_t> out(n);
      tumble::cpu::test::withThreads(threads, [&] {
        std::size_t bytes = 0;
        exclusiveSum<std::uint32_t>(nullptr, bytes, in.data(), out.data(), n);
        std::vector<unsigned char> temp(bytes);
        exclusiveSum<std::uint32_t>(temp.data(), bytes, in.data(), out.data(), n);
      });
      EXPECT_TRUE(sameArray(out, expected));
    }
  }
}

}  // namespace
