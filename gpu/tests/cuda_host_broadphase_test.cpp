// SPDX-License-Identifier: MIT
// The CUDA pipeline's broadphase (gpu/src/broadphase.hpp), run on the host backend of its
// execution layer, against the CPU broadphase (cpu/src/broadphase.cpp), array by array: the
// frame, the records (recFirst, inv), the forward list (nbrOffsets, nbr) and the transpose
// (backOffsets, back), with 1 and 2 threads. The same code nvcc compiles for the device; what is
// left to a GPU is the device backend (launches, the block trees, CUB). The block tree's own steps
// (exec.hpp threadShare, treeStep) are run here thread by thread against the sequential fold.
// Clouds: the hard cases of SPEC §3 and random clouds (their seeds are printed), with the
// automatic and a small cell size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "tumble/cpu/broadphase.hpp"  // the CPU broadphase, the reference
#include "broadphase.hpp"  // the CUDA pipeline's (gpu/src), over the execution layer
#include "exec/host_exec.hpp"
#include "tumble/validation/scenes.hpp"

using namespace tumble;
using HostExec = gpu::exec::HostExec;

namespace {

template <typename T>
std::vector<T> firstOf(const T* v, std::size_t count) {
  return std::vector<T>(v, v + count);
}

void expectSameAsCpu(const ParticleCloud& c, const BroadphaseParams& params, const std::string& what) {
  SCOPED_TRACE(what);
  const auto n = static_cast<std::uint32_t>(c.size());
  float maxR = 0.0f;
  for (float r : c.r) maxR = std::max(maxR, r);
  const BroadphaseInput in{c.x.data(), c.y.data(), c.z.data(), c.r.data(), c.body.data(), n, maxR,
                           detail::sizingRadius(c.r.data(), n)};
  cpu::detail::Broadphase ref;
  double seconds[kNumPhases] = {};
  ref.run(in, params, seconds);
  const std::uint32_t numRec = ref.numRecords();
  const std::size_t numEntries = ref.numPairs();
  for (const int threads : {1, 2}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    const HostExec::Stream s(threads);
    gpu::detail::Broadphase<HostExec> got;
    got.run(in, params, s, nullptr);  // the input is host memory: the host backend's device memory
    s.synchronize();
    EXPECT_EQ(std::memcmp(&got.frame(), &ref.frame(), sizeof(SweepFrame)), 0) << "the sweep frames differ";
    ASSERT_EQ(got.numRecords(), numRec);
    ASSERT_EQ(got.numPairs(), numEntries);
    ASSERT_EQ(firstOf(got.recFirst.data(), std::size_t(n) + 1), firstOf(ref.recFirst.data(), std::size_t(n) + 1));
    ASSERT_EQ(firstOf(got.inv.data(), numRec), firstOf(ref.inv.data(), numRec));
    ASSERT_EQ(firstOf(got.nbrOffsets.data(), std::size_t(numRec) + 1),
              firstOf(ref.nbrOffsets.data(), std::size_t(numRec) + 1));
    ASSERT_EQ(firstOf(got.nbr.data(), numEntries), firstOf(ref.nbr.data(), numEntries));
    EXPECT_EQ(firstOf(got.backOffsets.data(), std::size_t(n) + 1),
              firstOf(ref.backOffsets.data(), std::size_t(n) + 1));
    EXPECT_EQ(firstOf(got.back.data(), numEntries), firstOf(ref.back.data(), numEntries));
    EXPECT_EQ(got.sortedPairs(n, s), ref.sortedPairs(n));
  }
}

// The device's fold of each chunk (exec.hpp: threadShare per thread, then treeStep level by
// level, as CudaExec's reduceTreeKernel runs them), thread by thread on the host.
template <class Op>
typename Op::Value deviceTreeFold(const Op& op, std::uint32_t n, std::uint32_t chunk, std::uint32_t c) {
  using gpu::exec::kBlock;
  std::vector<typename Op::Value> part(kBlock);
  for (std::uint32_t t = 0; t < kBlock; ++t) part[t] = gpu::exec::threadShare(op, n, chunk, c, t);
  for (std::uint32_t d = 1; d < kBlock; d <<= 1)
    for (std::uint32_t t = 0; t < kBlock; ++t) gpu::exec::treeStep(op, part.data(), t, d);
  return part[0];
}

}  // namespace

TEST(CudaHostBroadphase, GivesTheCpuArraysOnTheHardCases) {
  const std::uint64_t seed = 20261205;
  std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
  for (const validation::NamedCloud& k : validation::hardCases(seed)) {
    if (k.cloud.size() == 0) continue;  // both runs stop before the frame
    expectSameAsCpu(k.cloud, BroadphaseParams{}, k.name);
    float rMin = std::numeric_limits<float>::max();
    for (float r : k.cloud.r) rMin = std::min(rMin, r);
    BroadphaseParams small;
    small.cellSize = rMin;  // many records per particle
    expectSameAsCpu(k.cloud, small, k.name + ", cell size " + std::to_string(rMin));
  }
}

TEST(CudaHostBroadphase, GivesTheCpuArraysOnRandomClouds) {
  struct Case {
    std::uint32_t n;
    float box, rMin, rMax;
    std::uint32_t bodySize;
  };
  // Sizes across the 4096-particle chunks and the 256-element blocks; dense and sparse.
  const Case cases[] = {{2, 1.0f, 0.3f, 0.6f, 1},       {255, 3.0f, 0.1f, 0.3f, 1},  {4097, 12.0f, 0.1f, 0.4f, 8},
                        {9000, 15.0f, 0.05f, 0.5f, 3}, {20000, 40.0f, 0.2f, 0.2f, 1}};
  std::uint64_t seed = 77;
  for (const Case& k : cases) {
    std::printf("n %u, seed %llu\n", k.n, static_cast<unsigned long long>(seed));
    const ParticleCloud c = validation::randomCloud(k.n, seed, k.box, k.rMin, k.rMax, k.bodySize);
    expectSameAsCpu(c, BroadphaseParams{}, "n " + std::to_string(k.n) + ", seed " + std::to_string(seed));
    BroadphaseParams small;
    small.cellSize = k.rMin;
    expectSameAsCpu(c, small, "n " + std::to_string(k.n) + ", cell size rMin, seed " + std::to_string(seed));
    ++seed;
  }
}

// The device's block tree on chunks whose extrema tie (−0 against +0, equal values at many
// indices) and hold non-finite particles: the same bits as the host's sequential fold
// (foldRange), firstBad included; and on 64-bit sums of counts near 2^32.
TEST(CudaHostBroadphase, DeviceTreeEqualsTheSequentialFold) {
  using namespace tumble::detail;
  std::vector<float> x(2 * kChunk), y(2 * kChunk), z(2 * kChunk), r(2 * kChunk, 1.0f);
  std::vector<std::uint32_t> body(2 * kChunk, 0), counts(2 * kChunk);
  for (std::uint32_t i = 0; i < 2 * kChunk; ++i) {
    x[i] = (i % 2 == 0) ? 0.0f : -0.0f;
    y[i] = (i % 7 == 3) ? 5.0f : -5.0f;
    z[i] = static_cast<float>(i % 13) - 6.0f;
    counts[i] = 0xFFFFFFF0u - i;
  }
  y[1000] = std::nanf("");
  r[77] = std::numeric_limits<float>::infinity();
  x[kChunk + 5] = std::numeric_limits<float>::infinity();
  for (std::uint32_t n : {2 * kChunk, kChunk + 6, kChunk, kChunk - 5, 17u, 1u}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const BroadphaseInput in{x.data(), y.data(), z.data(), r.data(), body.data(), n, 1.0f, 0.0f};
    const gpu::detail::BoundsOp bounds{in};
    const gpu::detail::CountSumOp sums{counts.data()};
    for (std::uint32_t c = 0; c * kChunk < n; ++c) {
      const std::uint32_t begin = c * kChunk, end = std::min(n, begin + kChunk);
      const BoundsPartial tree = deviceTreeFold(bounds, n, kChunk, c);
      const BoundsPartial seq = gpu::exec::foldRange(bounds, begin, end);
      EXPECT_EQ(std::memcmp(&tree, &seq, sizeof seq), 0) << "bounds of chunk " << c;
      EXPECT_EQ(deviceTreeFold(sums, n, kChunk, c), gpu::exec::foldRange(sums, begin, end)) << "sum of chunk " << c;
    }
  }
}
