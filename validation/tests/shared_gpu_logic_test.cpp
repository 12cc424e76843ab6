// SPDX-License-Identifier: MIT
// The CUDA broadphase's logic on the CPU (issue 10, item 3): gpu/src/broadphase.cu's stage list,
// step by step, with the same shared TUMBLE_HD functions its kernels call (one loop iteration per
// thread, the bounds block's tree level by level), the project's radix sort and scan in place of
// CUB's (the same contract), and every array compared with the CPU broadphase's: the frame, the
// records (recFirst, inv), the forward list (nbrOffsets, nbr) and the transpose (backOffsets,
// back). What this leaves to the GPU is launch configuration and CUB. Clouds: the hard cases of
// SPEC §3 and random clouds (their seeds are printed), with the automatic and a small cell size.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "broadphase.hpp"  // cpu/src: the CPU broadphase, the reference
#include "tumble/cpu/radix_sort.hpp"
#include "tumble/cpu/scan.hpp"
#include "tumble/kernels/sweep.hpp"
#include "tumble/sweep_frame.hpp"
#include "tumble/validation/scenes.hpp"

using namespace tumble;

namespace {

// What gpu/src/broadphase.cu's Broadphase::run leaves on the device.
struct CudaBroadphaseArrays {
  SweepFrame frame{};
  std::vector<std::uint32_t> recFirst, inv, nbrOffsets, nbr, backOffsets, back;
};

std::vector<std::uint32_t> scan(const std::vector<std::uint32_t>& counts) {
  std::vector<std::uint32_t> out(counts.size());
  std::size_t bytes = 0;
  cpu::exclusiveSum<std::uint32_t>(nullptr, bytes, counts.data(), out.data(), counts.size());
  std::vector<std::byte> temp(bytes);
  cpu::exclusiveSum<std::uint32_t>(temp.data(), bytes, counts.data(), out.data(), counts.size());
  return out;
}

template <typename K>
void sortPairs(const std::vector<K>& keys, std::vector<K>* skeys, const std::vector<std::uint32_t>& vals,
               std::vector<std::uint32_t>* svals, int endBit) {
  const std::size_t n = keys.size();
  skeys->assign(n, 0);
  svals->assign(n, 0);
  std::size_t bytes = 0;
  cpu::radixSortPairs<K, std::uint32_t>(nullptr, bytes, keys.data(), skeys->data(), vals.data(), svals->data(), n, 0,
                                        endBit);
  std::vector<std::byte> temp(bytes);
  cpu::radixSortPairs<K, std::uint32_t>(temp.data(), bytes, keys.data(), skeys->data(), vals.data(), svals->data(), n,
                                        0, endBit);
}

// Broadphase::computeFrame and Broadphase::run of gpu/src/broadphase.cu, first detection (the
// axis is due), on the CPU.
CudaBroadphaseArrays runCudaBroadphaseOnCpu(const BroadphaseInput& in, const BroadphaseParams& params) {
  using namespace tumble::detail;
  CudaBroadphaseArrays out;
  const std::uint32_t n = in.n;
  // boundsKernel: one block per chunk, thread t on its contiguous share, then the tree.
  const std::uint32_t numChunks = (n + kChunk - 1) / kChunk;
  std::vector<BoundsPartial> part(numChunks);
  for (std::uint32_t c = 0; c < numChunks; ++c) {
    BoundsPartial sh[kBoundsThreads];
    for (std::uint32_t t = 0; t < kBoundsThreads; ++t) {
      const std::uint32_t begin = c * kChunk + t * kBoundsPerThread;
      sh[t] = boundsOfRange(in, begin, std::min(n, begin + kBoundsPerThread));
    }
    for (std::uint32_t d = 1; d < kBoundsThreads; d <<= 1)
      for (std::uint32_t t = 0; t < kBoundsThreads; ++t) boundsTreeStep(sh, t, d);
    part[c] = sh[0];
  }
  const BoundsPartial b = combineBounds(part.data(), numChunks);
  // covarianceKernel: each chunk summed by one thread in index order.
  Vec3f axis{0.0f, 0.0f, 1.0f};
  if (n >= 2) {
    std::vector<double> cov(9 * std::size_t(numChunks), 0.0);
    for (std::uint32_t c = 0; c < numChunks; ++c)
      for (std::uint32_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i)
        addCovariance(&cov[9 * std::size_t(c)], in.x[i], in.y[i], in.z[i], in.x[0], in.y[0], in.z[0]);
    axis = principalAxisFromPartials(cov.data(), numChunks, n);
  }
  const int cellBits = computeFrame(b, axis, in.maxRadius, in.cellRadius, params, &out.frame);
  const SweepFrame& f = out.frame;

  // keysCountKernel, scan, keysEmitKernel.
  std::vector<ParticleRow> prow(n);
  std::vector<std::uint32_t> counts(std::size_t(n) + 1, 0);
  for (std::uint32_t i = 0; i < n; ++i) countRecords(in, f, prow.data(), counts.data(), i);
  out.recFirst = scan(counts);
  const std::uint32_t numRec = out.recFirst[n];
  std::vector<std::uint64_t> keys(numRec), skeys;
  std::vector<std::uint32_t> vals(numRec), svals, recParticle(numRec);
  for (std::uint32_t i = 0; i < n; ++i)
    emitRecords(in, f, prow.data(), counts.data(), out.recFirst.data(), keys.data(), vals.data(), recParticle.data(),
                i);
  // radixSortPairs(records), gatherKernel.
  sortPairs(keys, &skeys, vals, &svals, 32 + cellBits);
  out.inv.assign(numRec, 0);
  std::vector<std::uint32_t> sp(numRec);
  std::vector<ParticleRow> srow(numRec);
  for (std::uint32_t s = 0; s < numRec; ++s)
    gatherRecord(svals.data(), recParticle.data(), prow.data(), s, out.inv.data(), sp.data(), srow.data());
  // sweepCountKernel, scan, sweepEmitKernel.
  const SweepWindow w = sweepWindow(in.maxRadius, f);
  const SweepRecords args{skeys.data(), srow.data(), sp.data(), numRec, f, w.reach, w.maxWindow};
  std::vector<std::uint32_t> nbrCount(std::size_t(numRec) + 1, 0);
  for (std::uint32_t s = 0; s < numRec; ++s) nbrCount[s] = sweepRecord<false>(args, s, nullptr, nullptr, 0u);
  out.nbrOffsets = scan(nbrCount);
  const std::uint32_t numEntries = out.nbrOffsets[numRec];
  out.nbr.assign(numEntries, 0);
  std::vector<std::uint32_t> owner(numEntries, 0);
  for (std::uint32_t s = 0; s < numRec; ++s)
    if (out.nbrOffsets[s + 1] != out.nbrOffsets[s])
      sweepRecord<true>(args, s, out.nbr.data(), owner.data(), out.nbrOffsets[s]);
  // radixSortPairs(transpose), backOffsetsKernel.
  std::vector<std::uint32_t> bkeys;
  int nBits = 1;
  while (nBits < 32 && ((n - 1) >> nBits) != 0) ++nBits;
  sortPairs(out.nbr, &bkeys, owner, &out.back, nBits);
  out.backOffsets.assign(std::size_t(n) + 1, 0);
  for (std::uint32_t i = 0; i <= n; ++i) out.backOffsets[i] = lowerBound(bkeys.data(), numEntries, i);
  return out;
}

template <typename T>
std::vector<T> firstOf(const std::vector<T>& v, std::size_t count) {
  return std::vector<T>(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(count));
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
  const CudaBroadphaseArrays got = runCudaBroadphaseOnCpu(in, params);
  EXPECT_EQ(std::memcmp(&got.frame, &ref.frame(), sizeof(SweepFrame)), 0) << "the sweep frames differ";
  const std::uint32_t numRec = ref.numRecords();
  ASSERT_EQ(got.recFirst, firstOf(ref.recFirst, std::size_t(n) + 1));
  ASSERT_EQ(got.inv, firstOf(ref.inv, numRec));
  ASSERT_EQ(got.nbrOffsets, firstOf(ref.nbrOffsets, std::size_t(numRec) + 1));
  ASSERT_EQ(got.nbr, firstOf(ref.nbr, ref.numPairs()));
  EXPECT_EQ(got.backOffsets, firstOf(ref.backOffsets, std::size_t(n) + 1));
  EXPECT_EQ(got.back, firstOf(ref.back, ref.numPairs()));
}

}  // namespace

TEST(SharedGpuLogicTest, CudaBroadphaseStepsGiveTheCpuArraysOnTheHardCases) {
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

TEST(SharedGpuLogicTest, CudaBroadphaseStepsGiveTheCpuArraysOnRandomClouds) {
  struct Case {
    std::uint32_t n;
    float box, rMin, rMax;
    std::uint32_t bodySize;
  };
  // Sizes across the 4096-particle chunks and the 256-thread bounds blocks; dense and sparse.
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

// The bounds block's tree on chunks whose extrema tie (−0 against +0, equal values at many
// indices) and hold non-finite particles: the same bits as the CPU's sequential chunk loop,
// firstBad included.
TEST(SharedGpuLogicTest, BoundsTreeEqualsTheSequentialChunk) {
  using namespace tumble::detail;
  std::vector<float> x(kChunk), y(kChunk), z(kChunk), r(kChunk, 1.0f);
  std::vector<std::uint32_t> body(kChunk, 0);
  for (std::uint32_t i = 0; i < kChunk; ++i) {
    x[i] = (i % 2 == 0) ? 0.0f : -0.0f;
    y[i] = (i % 7 == 3) ? 5.0f : -5.0f;
    z[i] = static_cast<float>(i % 13) - 6.0f;
  }
  y[1000] = std::nanf("");
  r[77] = std::numeric_limits<float>::infinity();
  const BroadphaseInput in{x.data(), y.data(), z.data(), r.data(), body.data(), kChunk, 1.0f, 0.0f};
  for (std::uint32_t n : {kChunk, kChunk - 5, 17u, 1u}) {
    BroadphaseInput part = in;
    part.n = n;
    BoundsPartial sh[kBoundsThreads];
    for (std::uint32_t t = 0; t < kBoundsThreads; ++t) {
      const std::uint32_t begin = t * kBoundsPerThread;
      sh[t] = boundsOfRange(part, begin, std::min(n, begin + kBoundsPerThread));
    }
    for (std::uint32_t d = 1; d < kBoundsThreads; d <<= 1)
      for (std::uint32_t t = 0; t < kBoundsThreads; ++t) boundsTreeStep(sh, t, d);
    const BoundsPartial want = boundsOfRange(part, 0, n);
    EXPECT_EQ(std::memcmp(&sh[0], &want, sizeof want), 0) << "n = " << n;
  }
}
