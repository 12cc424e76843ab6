// SPDX-License-Identifier: MIT
// CUB's radix sort and scan (gpu/src/cub_primitives.cuh) against the project's
// (tumble::cpu::radixSortPairs, exclusiveSum) on the same inputs, with the sizes and bit ranges
// of the CPU primitive tests (cpu/tests): the same keys, values and sums, bit for bit. Both
// pipelines' results rest on these being the same permutation (stable, on the same bits).
#include "tumble/config.hpp"

#if TUMBLE_HAS_CUDA
#include <cuda_runtime_api.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <vector>

#include "tumble_test/arrays.hpp"  // sameArray, testSizes
#include "cub_primitives.cuh"
#include "tumble/cpu/radix_sort.hpp"
#include "tumble/cpu/scan.hpp"
#include "tumble/factory.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;
using cpu::test::sameArray;

namespace {

#define CHECK_CUDA(expr) ASSERT_EQ((expr), cudaSuccess) << #expr

// A device copy of a host array (freed at scope exit).
template <class T>
struct Device {
  T* p = nullptr;
  explicit Device(std::size_t n) {
    void* q = nullptr;
    if (cudaMalloc(&q, (n > 0 ? n : 1) * sizeof(T)) == cudaSuccess) p = static_cast<T*>(q);
  }
  ~Device() { (void)cudaFree(p); }
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;
};

template <class K>
std::vector<K> randomKeys(std::size_t n, std::uint64_t seed, int variant) {
  std::mt19937_64 rng(seed);
  std::vector<K> k(n);
  for (auto& v : k) {
    const std::uint64_t r = rng();
    v = variant == 0 ? K(r) : variant == 1 ? K(r & 0xFFFFF) : K(r % 7);  // uniform, low bits, few distinct
  }
  return k;
}

template <class K>
void checkSort(std::size_t n, int beginBit, int endBit, int variant, std::uint64_t seed) {
  SCOPED_TRACE("n " + std::to_string(n) + ", bits [" + std::to_string(beginBit) + ", " + std::to_string(endBit) +
               "), keys " + std::to_string(variant) + ", seed " + std::to_string(seed));
  const std::vector<K> keys = randomKeys<K>(n, seed, variant);
  std::vector<std::uint32_t> vals(n);
  for (std::size_t i = 0; i < n; ++i) vals[i] = static_cast<std::uint32_t>(i);
  // The project's sort.
  std::vector<K> wantKeys(n);
  std::vector<std::uint32_t> wantVals(n);
  std::size_t bytes = 0;
  cpu::radixSortPairs<K, std::uint32_t>(nullptr, bytes, keys.data(), wantKeys.data(), vals.data(), wantVals.data(), n,
                                        beginBit, endBit);
  std::vector<std::byte> temp(bytes);
  cpu::radixSortPairs<K, std::uint32_t>(temp.data(), bytes, keys.data(), wantKeys.data(), vals.data(),
                                        wantVals.data(), n, beginBit, endBit);
  // CUB's.
  Device<K> kin(n), kout(n);
  Device<std::uint32_t> vin(n), vout(n);
  ASSERT_TRUE(kin.p && kout.p && vin.p && vout.p) << "cudaMalloc failed";
  CHECK_CUDA(cudaMemcpy(kin.p, keys.data(), n * sizeof(K), cudaMemcpyHostToDevice));
  CHECK_CUDA(cudaMemcpy(vin.p, vals.data(), n * sizeof(std::uint32_t), cudaMemcpyHostToDevice));
  std::size_t dbytes = 0;
  const auto count = static_cast<std::uint32_t>(n);
  CHECK_CUDA(gpu::detail::radixSortPairs(nullptr, dbytes, kin.p, kout.p, vin.p, vout.p, count, beginBit, endBit, 0));
  Device<unsigned char> dtemp(dbytes);
  ASSERT_TRUE(dtemp.p);
  CHECK_CUDA(gpu::detail::radixSortPairs(dtemp.p, dbytes, kin.p, kout.p, vin.p, vout.p, count, beginBit, endBit, 0));
  CHECK_CUDA(cudaDeviceSynchronize());
  std::vector<K> gotKeys(n);
  std::vector<std::uint32_t> gotVals(n);
  CHECK_CUDA(cudaMemcpy(gotKeys.data(), kout.p, n * sizeof(K), cudaMemcpyDeviceToHost));
  CHECK_CUDA(cudaMemcpy(gotVals.data(), vout.p, n * sizeof(std::uint32_t), cudaMemcpyDeviceToHost));
  EXPECT_TRUE(sameArray(gotVals, wantVals));
  EXPECT_TRUE(sameArray(gotKeys, wantKeys));
}

template <class K>
void checkSorts(std::initializer_list<std::pair<int, int>> ranges) {
  std::uint64_t seed = sizeof(K) == 8 ? 6400 : 3200;
  for (std::size_t n : cpu::test::testSizes(20240611, 200000))
    for (const auto& [b, e] : ranges)
      for (int variant = 0; variant < 3; ++variant) checkSort<K>(n, b, e, variant, seed++);
}

}  // namespace

// The bit ranges of cpu/tests/radix_sort_test.cpp.
TEST(CudaPrimitives, RadixSortPairs64EqualsTheProjectSort) {
  TUMBLE_NEED_CUDA(cudaStatus());
  checkSorts<std::uint64_t>({{0, 64}, {0, 20}, {8, 40}, {0, 41}, {63, 64}, {13, 13}});
}

TEST(CudaPrimitives, RadixSortPairs32EqualsTheProjectSort) {
  TUMBLE_NEED_CUDA(cudaStatus());
  checkSorts<std::uint32_t>({{0, 32}, {4, 12}, {0, 20}, {31, 32}, {7, 7}});
}

TEST(CudaPrimitives, ExclusiveSumEqualsTheProjectScan) {
  TUMBLE_NEED_CUDA(cudaStatus());
  std::mt19937_64 rng(987654321);
  for (std::size_t n : cpu::test::testSizes(987654321, 300000)) {
    SCOPED_TRACE("n " + std::to_string(n));
    std::vector<std::uint32_t> in(n), want(n), got(n);
    for (auto& v : in) v = static_cast<std::uint32_t>(rng() % 5000);
    std::size_t bytes = 0;
    cpu::exclusiveSum<std::uint32_t>(nullptr, bytes, in.data(), want.data(), n);
    std::vector<std::byte> temp(bytes);
    cpu::exclusiveSum<std::uint32_t>(temp.data(), bytes, in.data(), want.data(), n);
    Device<std::uint32_t> din(n), dout(n);
    ASSERT_TRUE(din.p && dout.p);
    CHECK_CUDA(cudaMemcpy(din.p, in.data(), n * sizeof(std::uint32_t), cudaMemcpyHostToDevice));
    std::size_t dbytes = 0;
    CHECK_CUDA(gpu::detail::exclusiveSum(nullptr, dbytes, din.p, dout.p, static_cast<std::uint32_t>(n), 0));
    Device<unsigned char> dtemp(dbytes);
    ASSERT_TRUE(dtemp.p);
    CHECK_CUDA(gpu::detail::exclusiveSum(dtemp.p, dbytes, din.p, dout.p, static_cast<std::uint32_t>(n), 0));
    CHECK_CUDA(cudaDeviceSynchronize());
    CHECK_CUDA(cudaMemcpy(got.data(), dout.p, n * sizeof(std::uint32_t), cudaMemcpyDeviceToHost));
    EXPECT_TRUE(sameArray(got, want));
  }
}
#endif  // TUMBLE_HAS_CUDA
