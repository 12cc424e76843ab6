// SPDX-License-Identifier: MIT
// CUDA broadphase (SPEC §3), the stage-by-stage twin of cpu/src/broadphase.cpp.
//
// Design notes
// - Same bits as the CPU. Every per-element step is a shared TUMBLE_HD function of core/, run
//   on the CPU too: the CPU pipeline calls the key, bounds and covariance steps itself
//   (countRecords, emitRecords, boundsOfRange, addCovariance), and the steps only this file
//   launches (boundsTreeStep, gatherRecord, sweepRecord, lowerBound: sweep_frame.hpp and
//   kernels/sweep.hpp) are run in this file's order on the CPU by
//   validation/tests/shared_gpu_logic_test.cpp, which compares every array with the CPU
//   broadphase's. With --fmad=false (TUMBLE_STRICT_FP) every key, every sorted position and
//   every pair is the same. What is left here is launch configuration and CUB: the radix sorts
//   are CUB's stable LSD sorts over the same bit ranges as the CPU's stable sorts, with the
//   unsorted record number as value, so the permutation is unique.
// - Bounds. Each 4096-particle chunk (the CPU's kChunk) is reduced by one block whose threads
//   take 16 contiguous particles each and are combined as a tree over contiguous ranges, in
//   order; chunk partials are merged on the host in chunk order, as on the CPU.
// - Covariance. Summed in double per chunk sequentially (one thread walks the chunk in index
//   order, reading it through shared memory), as the CPU's per-chunk loop; the partials go to
//   the host, which adds them in chunk order and runs the same Eigen solve
//   (core/src/sweep_frame.cpp). It runs only when the axis is due (every pcaEvery steps) and costs
//   ~4096 dependent double adds per chunk.
// - Output capacity. The CPU's sweep appends into fixed-size chunk buffers; here the sweep runs
//   twice instead, count → exclusive scan → emit (STYLE §5), which yields the same nbrOffsets and
//   nbr arrays with no atomics and no overflow path. The totals are summed in 64 bits first and
//   refused beyond the 32-bit scans (checkTotal). The transpose is CUB's stable sort of (other,
//   owner) by other, like the CPU's.
#include "broadphase.cuh"

#include <algorithm>
#include <string>

#include "cub_primitives.cuh"
#include "tumble/config.hpp"
#include "tumble/error.hpp"
#include "tumble/kernels/sweep.hpp"

namespace tumble::gpu::detail {
namespace {

constexpr std::uint32_t kNone = 0xFFFFFFFFu;
static_assert(kBlock == kBoundsThreads, "the bounds pass runs one kBoundsThreads block per chunk");

// --- Axis ----------------------------------------------------------------------------------

// One block per chunk: each thread's contiguous share (boundsOfRange), then the tree of
// boundsTreeStep (sweep_frame.hpp: the chunk's bounds bit for bit, as the CPU's).
__global__ void __launch_bounds__(kBlock) boundsKernel(BroadphaseInput in, BoundsPartial* outPart) {
  __shared__ BoundsPartial sh[kBlock];
  const std::uint32_t t = threadIdx.x;
  const std::uint32_t begin = blockIdx.x * kChunk + t * kBoundsPerThread;
  sh[t] = boundsOfRange(in, begin, in.n < begin + kBoundsPerThread ? in.n : begin + kBoundsPerThread);
  __syncthreads();
  for (std::uint32_t d = 1; d < kBlock; d <<= 1) {
    boundsTreeStep(sh, t, d);
    __syncthreads();
  }
  if (t == 0) outPart[blockIdx.x] = sh[0];
}

// One block per chunk: the chunk staged through shared memory, then summed by one thread in index
// order (addCovariance: the CPU's per-chunk loop, the same bits).
__global__ void __launch_bounds__(kBlock) covarianceKernel(BroadphaseInput in, double* outPart) {
  __shared__ float tx[kBlock], ty[kBlock], tz[kBlock];
  const std::uint32_t begin = blockIdx.x * kChunk;
  const std::uint32_t end = in.n < begin + kChunk ? in.n : begin + kChunk;
  // Shift by particle 0: keeps the sums well conditioned (float → double is exact).
  const double sx = in.x[0], sy = in.y[0], sz = in.z[0];
  double a[9] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (std::uint32_t base = begin; base < end; base += kBlock) {
    const std::uint32_t i = base + threadIdx.x;
    if (i < end) {
      tx[threadIdx.x] = in.x[i];
      ty[threadIdx.x] = in.y[i];
      tz[threadIdx.x] = in.z[i];
    }
    __syncthreads();
    if (threadIdx.x == 0) {
      const std::uint32_t m = end - base < kBlock ? end - base : kBlock;
      for (std::uint32_t k = 0; k < m; ++k) addCovariance(a, tx[k], ty[k], tz[k], sx, sy, sz);
    }
    __syncthreads();
  }
  if (threadIdx.x == 0)
    for (int k = 0; k < 9; ++k) outPart[9 * std::size_t(blockIdx.x) + k] = a[k];
}

// --- Totals --------------------------------------------------------------------------------

// The 64-bit sum of each kChunk counts (integers: exact in any order), one block per chunk, so
// that a total beyond the 32-bit scans is refused (checkTotal) before it wraps.
__global__ void __launch_bounds__(kBlock) chunkSumKernel(const std::uint32_t* counts, std::uint32_t n,
                                                        unsigned long long* outPart) {
  __shared__ unsigned long long sh[kBlock];
  const std::uint32_t t = threadIdx.x, begin = blockIdx.x * kChunk;
  const std::uint32_t end = n < begin + kChunk ? n : begin + kChunk;
  unsigned long long s = 0;
  for (std::uint32_t i = begin + t; i < end; i += kBlock) s += counts[i];
  sh[t] = s;
  __syncthreads();
  for (std::uint32_t d = kBlock / 2; d > 0; d >>= 1) {
    if (t < d) sh[t] += sh[t + d];
    __syncthreads();
  }
  if (t == 0) outPart[blockIdx.x] = sh[0];
}

// --- Keys ----------------------------------------------------------------------------------

// Twin of the CPU's first key loop; thread n writes the trailing zero of counts.
__global__ void keysCountKernel(BroadphaseInput in, SweepFrame f, ParticleRow* prow, std::uint32_t* counts) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < in.n) countRecords(in, f, prow, counts, i);
  if (i == in.n) counts[i] = 0;
}

// Twin of the CPU's second key loop: particle i's records in (a, b) row-major order.
__global__ void keysEmitKernel(BroadphaseInput in, SweepFrame f, const ParticleRow* prow, const std::uint32_t* counts,
                               const std::uint32_t* first, std::uint64_t* keys, std::uint32_t* vals,
                               std::uint32_t* recParticle) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < in.n) emitRecords(in, f, prow, counts, first, keys, vals, recParticle, i);
}

// --- Sweep ---------------------------------------------------------------------------------

__global__ void gatherKernel(const std::uint32_t* svals, const std::uint32_t* recParticle, const ParticleRow* prow,
                             std::uint32_t numRec, std::uint32_t* inv, std::uint32_t* sp, ParticleRow* srow) {
  const std::uint32_t s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s < numRec) gatherRecord(svals, recParticle, prow, s, inv, sp, srow);
}

// The sweep (sweepRecord, kernels/sweep.hpp) in two passes.
// Count pass; thread numRec writes the trailing zero of the counts.
__global__ void sweepCountKernel(SweepRecords a, std::uint32_t* nbrCount) {
  const std::uint32_t s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s > a.numRec) return;
  nbrCount[s] = s == a.numRec ? 0u : sweepRecord<false>(a, s, nullptr, nullptr, 0u);
}

// Emit pass: the same walk, writing at the scanned offsets (one writer per entry).
__global__ void sweepEmitKernel(SweepRecords a, const std::uint32_t* nbrOffsets, std::uint32_t* nbr,
                                std::uint32_t* owner) {
  const std::uint32_t s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s >= a.numRec) return;
  const std::uint32_t base = nbrOffsets[s];
  if (nbrOffsets[s + 1] == base) return;  // most records have no contact at all
  sweepRecord<true>(a, s, nbr, owner, base);
}

// backOffsets[i] = lowerBound(bkeys, numEntries, i): one writer per offset.
__global__ void backOffsetsKernel(const std::uint32_t* bkeys, std::uint32_t numEntries, std::uint32_t n,
                                  std::uint32_t* backOffsets) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i <= n) backOffsets[i] = lowerBound(bkeys, numEntries, i);
}

}  // namespace

std::uint64_t Broadphase::total(const std::uint32_t* counts, std::uint32_t n, const StreamContext& ctx) {
  const std::uint32_t numChunks = (n + kChunk - 1) / kChunk;
  if (numChunks == 0) return 0;
  chunkSumKernel<<<numChunks, kBlock, 0, ctx.stream()>>>(counts, n, m_sumPart.grow(numChunks));
  TUMBLE_CUDA_AFTER_LAUNCH(ctx, "chunkSumKernel");
  m_hostSum.resize(numChunks);
  m_sumPart.download(m_hostSum.data(), numChunks, ctx.stream());
  ctx.synchronize();
  std::uint64_t s = 0;
  for (unsigned long long v : m_hostSum) s += v;
  return s;
}

void Broadphase::computeFrame(const BroadphaseInput& in, const BroadphaseParams& params, const StreamContext& ctx) {
  const cudaStream_t stream = ctx.stream();
  const std::uint32_t numChunks = (in.n + kChunk - 1) / kChunk;
  boundsKernel<<<numChunks, kBlock, 0, stream>>>(in, m_boundsPart.grow(numChunks));
  TUMBLE_CUDA_AFTER_LAUNCH(ctx, "boundsKernel");
  const bool newAxis = m_runsSinceAxis < 0 || m_runsSinceAxis >= std::max(1, params.pcaEvery);
  // Launched before the bounds are checked, to save a round trip; with a non-finite particle
  // its result is discarded (the CPU computes it only after the check; same observable result).
  const bool covariance = newAxis && in.n >= 2;
  if (covariance) {
    covarianceKernel<<<numChunks, kBlock, 0, stream>>>(in, m_covPart.grow(9 * std::size_t(numChunks)));
    TUMBLE_CUDA_AFTER_LAUNCH(ctx, "covarianceKernel");
  }
  m_hostBounds.resize(numChunks);
  m_boundsPart.download(m_hostBounds.data(), numChunks, stream);
  if (covariance) {
    m_hostCov.resize(9 * std::size_t(numChunks));
    m_covPart.download(m_hostCov.data(), m_hostCov.size(), stream);
  }
  ctx.synchronize();

  const BoundsPartial b = combineBounds(m_hostBounds.data(), numChunks);
  if (b.firstBad != kNone)
    throw SimulationError("particle " + std::to_string(b.firstBad) + " has a non-finite position or radius",
                          b.firstBad);
  if (newAxis) {
    m_axis = covariance ? principalAxisFromPartials(m_hostCov.data(), numChunks, in.n) : Vec3f{0.0f, 0.0f, 1.0f};
    m_runsSinceAxis = 0;
  }
  ++m_runsSinceAxis;
  m_cellBits = detail::computeFrame(b, m_axis, in.maxRadius, in.cellRadius, params, &m_frame);
}

void Broadphase::run(const BroadphaseInput& in, const BroadphaseParams& params, const StreamContext& ctx,
                     PhaseTimer* timer) {
  const std::uint32_t n = in.n;
  const cudaStream_t stream = ctx.stream();
  m_numRecords = 0;
  m_numEntries = 0;
  m_hasRun = false;
  if (timer != nullptr) timer->mark(Phase::Axis, stream);
  if (n == 0) {
    TUMBLE_CUDA_CHECK(cudaMemsetAsync(recFirst.grow(1), 0, sizeof(std::uint32_t), stream));
    TUMBLE_CUDA_CHECK(cudaMemsetAsync(nbrOffsets.grow(1), 0, sizeof(std::uint32_t), stream));
    TUMBLE_CUDA_CHECK(cudaMemsetAsync(backOffsets.grow(1), 0, sizeof(std::uint32_t), stream));
    if (timer != nullptr)
      for (Phase p : {Phase::Keys, Phase::Sort, Phase::Sweep}) timer->mark(p, stream);
    m_hasRun = true;
    return;
  }
  computeFrame(in, params, ctx);
  const SweepFrame f = m_frame;

  // Keys: count records per particle, scan, emit (key, unsorted record number).
  if (timer != nullptr) timer->mark(Phase::Keys, stream);
  ParticleRow* prow = m_prow.grow(n);
  std::uint32_t* counts = m_counts.grow(std::size_t(n) + 1);
  std::uint32_t* first = recFirst.grow(std::size_t(n) + 1);
  keysCountKernel<<<blocksFor(std::uint64_t(n) + 1), kBlock, 0, stream>>>(in, f, prow, counts);
  TUMBLE_CUDA_AFTER_LAUNCH(ctx, "keysCountKernel");
  // The total in 64 bits before the 32-bit scan (it is also the scan's last offset, so it is the
  // only read-back here); device memory is checked by the allocations.
  const std::uint64_t numRec64 = total(counts, n, ctx);
  checkRecordTotal(numRec64, n, f.cellSize, in.maxRadius, 0, 0);
  std::size_t tempBytes = 0;
  TUMBLE_CUDA_CHECK(exclusiveSum(nullptr, tempBytes, counts, first, n + 1, stream));
  TUMBLE_CUDA_CHECK(exclusiveSum(m_temp.grow(tempBytes), tempBytes, counts, first, n + 1, stream));
  TUMBLE_CUDA_AFTER_LAUNCH(ctx, "exclusiveSum(record counts)");
  const auto numRec = static_cast<std::uint32_t>(numRec64);
  m_numRecords = numRec;
  std::uint64_t* keys = m_keys.grow(numRec);
  std::uint32_t* vals = m_vals.grow(numRec);
  std::uint32_t* recParticle = m_recParticle.grow(numRec);
  keysEmitKernel<<<blocksFor(n), kBlock, 0, stream>>>(in, f, prow, counts, first, keys, vals, recParticle);
  TUMBLE_CUDA_AFTER_LAUNCH(ctx, "keysEmitKernel");

  // Sort records by (cell, z): stable, bits [0, 32 + cellBits), as the CPU.
  if (timer != nullptr) timer->mark(Phase::Sort, stream);
  std::uint64_t* skeys = m_sortedKeys.grow(numRec);
  std::uint32_t* svals = m_sortedVals.grow(numRec);
  const int endBit = 32 + m_cellBits;
  TUMBLE_CUDA_CHECK(radixSortPairs(nullptr, tempBytes, keys, skeys, vals, svals, numRec, 0, endBit, stream));
  TUMBLE_CUDA_CHECK(
      radixSortPairs(m_temp.grow(tempBytes), tempBytes, keys, skeys, vals, svals, numRec, 0, endBit, stream));
  TUMBLE_CUDA_AFTER_LAUNCH(ctx, "radixSortPairs(records)");

  // Sweep: gather sorted rows, count, scan, emit; then the transpose.
  if (timer != nullptr) timer->mark(Phase::Sweep, stream);
  std::uint32_t* invp = inv.grow(numRec);
  std::uint32_t* sp = m_sp.grow(numRec);
  ParticleRow* srow = m_srow.grow(numRec);
  gatherKernel<<<blocksFor(numRec), kBlock, 0, stream>>>(svals, recParticle, prow, numRec, invp, sp, srow);
  TUMBLE_CUDA_AFTER_LAUNCH(ctx, "gatherKernel");
  const SweepWindow w = sweepWindow(in.maxRadius, f);
  const SweepRecords args{skeys, srow, sp, numRec, f, w.reach, w.maxWindow};
  std::uint32_t* nbrCount = m_nbrCount.grow(std::size_t(numRec) + 1);
  sweepCountKernel<<<blocksFor(std::uint64_t(numRec) + 1), kBlock, 0, stream>>>(args, nbrCount);
  TUMBLE_CUDA_AFTER_LAUNCH(ctx, "sweepCountKernel");
  const std::uint64_t numEntries64 = total(nbrCount, numRec, ctx);  // as the records' total
  checkTotal(numEntries64, kMaxEntries, 0, 0, n, "candidate pairs", kDenseCause);
  std::uint32_t* offs = nbrOffsets.grow(std::size_t(numRec) + 1);
  TUMBLE_CUDA_CHECK(exclusiveSum(nullptr, tempBytes, nbrCount, offs, numRec + 1, stream));
  TUMBLE_CUDA_CHECK(exclusiveSum(m_temp.grow(tempBytes), tempBytes, nbrCount, offs, numRec + 1, stream));
  TUMBLE_CUDA_AFTER_LAUNCH(ctx, "exclusiveSum(neighbour counts)");
  const auto numEntries = static_cast<std::uint32_t>(numEntries64);
  m_numEntries = numEntries;
  std::uint32_t* nb = nbr.grow(numEntries);
  std::uint32_t* owner = m_owner.grow(numEntries);
  std::uint32_t* bkeys = m_backKeys.grow(numEntries);
  std::uint32_t* bvals = back.grow(numEntries);
  if (numEntries > 0) {
    sweepEmitKernel<<<blocksFor(numRec), kBlock, 0, stream>>>(args, offs, nb, owner);
    TUMBLE_CUDA_AFTER_LAUNCH(ctx, "sweepEmitKernel");
    // Transpose: stable sort of (other, owner) by other over bits [0, bit_width(n − 1)).
    int nBits = 1;
    while (nBits < 32 && ((n - 1) >> nBits) != 0) ++nBits;  // max(1, std::bit_width(n − 1))
    TUMBLE_CUDA_CHECK(radixSortPairs(nullptr, tempBytes, nb, bkeys, owner, bvals, numEntries, 0, nBits, stream));
    TUMBLE_CUDA_CHECK(
        radixSortPairs(m_temp.grow(tempBytes), tempBytes, nb, bkeys, owner, bvals, numEntries, 0, nBits, stream));
    TUMBLE_CUDA_AFTER_LAUNCH(ctx, "radixSortPairs(transpose)");
  }
  std::uint32_t* boffs = backOffsets.grow(std::size_t(n) + 1);
  backOffsetsKernel<<<blocksFor(std::uint64_t(n) + 1), kBlock, 0, stream>>>(bkeys, numEntries, n, boffs);
  TUMBLE_CUDA_AFTER_LAUNCH(ctx, "backOffsetsKernel");
  m_hasRun = true;
#if TUMBLE_VALIDATE
  validate(n, stream);
#endif
}

void Broadphase::validate(std::uint32_t n, cudaStream_t stream) const {
  const std::uint32_t numRec = m_numRecords;
  const auto numEntries = static_cast<std::uint32_t>(m_numEntries);
  std::vector<std::uint64_t> skeys(numRec);
  std::vector<std::uint32_t> first(std::size_t(n) + 1), invh(numRec), offs(std::size_t(numRec) + 1), nb(numEntries),
      bkeys(numEntries), bvals(numEntries), boffs(std::size_t(n) + 1);
  m_sortedKeys.download(skeys.data(), skeys.size(), stream);
  recFirst.download(first.data(), first.size(), stream);
  inv.download(invh.data(), invh.size(), stream);
  nbrOffsets.download(offs.data(), offs.size(), stream);
  nbr.download(nb.data(), nb.size(), stream);
  m_backKeys.download(bkeys.data(), bkeys.size(), stream);
  back.download(bvals.data(), bvals.size(), stream);
  backOffsets.download(boffs.data(), boffs.size(), stream);
  TUMBLE_CUDA_CHECK(cudaStreamSynchronize(stream));
  auto fail = [](const std::string& what) { throw Error("TUMBLE_VALIDATE (CUDA broadphase): " + what); };
  if (first[0] != 0 || first[n] != numRec) fail("recFirst does not span the records");
  for (std::uint32_t i = 0; i < n; ++i)
    if (first[i + 1] <= first[i]) fail("particle " + std::to_string(i) + " has no record");
  for (std::uint32_t s = 1; s < numRec; ++s)
    if (skeys[s] < skeys[s - 1]) fail("sort keys not sorted at " + std::to_string(s));
  std::vector<char> seen(numRec, 0);
  for (std::uint32_t r = 0; r < numRec; ++r) {
    if (invh[r] >= numRec || seen[invh[r]]) fail("inv is not a permutation at record " + std::to_string(r));
    seen[invh[r]] = 1;
  }
  if (offs[0] != 0 || offs[numRec] != numEntries) fail("nbrOffsets does not span the entries");
  for (std::uint32_t s = 0; s < numRec; ++s)
    if (offs[s + 1] < offs[s]) fail("nbrOffsets decreases at " + std::to_string(s));
  for (std::uint32_t e = 0; e < numEntries; ++e) {
    if (nb[e] >= n || bvals[e] >= n) fail("entry " + std::to_string(e) + " names a particle out of range");
    if (e > 0 && bkeys[e] < bkeys[e - 1]) fail("transpose keys not sorted at " + std::to_string(e));
  }
  if (boffs[0] != 0 || boffs[n] != numEntries) fail("backOffsets does not span the entries");
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t e = boffs[i]; e < boffs[i + 1]; ++e)
      if (bkeys[e] != i) fail("backOffsets of particle " + std::to_string(i) + " are wrong");
}

std::vector<Pair> Broadphase::sortedPairs(std::uint32_t n, cudaStream_t stream) const {
  if (!m_hasRun) return {};
  std::vector<std::uint32_t> hFirst(std::size_t(n) + 1), hInv(m_numRecords), hOffs(std::size_t(m_numRecords) + 1),
      hNbr(m_numEntries);
  recFirst.download(hFirst.data(), hFirst.size(), stream);
  inv.download(hInv.data(), hInv.size(), stream);
  nbrOffsets.download(hOffs.data(), hOffs.size(), stream);
  nbr.download(hNbr.data(), hNbr.size(), stream);
  TUMBLE_CUDA_CHECK(cudaStreamSynchronize(stream));
  return detail::sortedPairs(n, hFirst.data(), hInv.data(), hOffs.data(), hNbr.data(), m_numEntries);
}

}  // namespace tumble::gpu::detail
