// SPDX-License-Identifier: MIT
// CPU broadphase (SPEC §3), after Liu et al. 2010: sweep and prune along the PCA axis with a
// 2-D subdivision of the perpendicular plane.
//
// Design notes
// - Exactness. Coordinates are projected relative to the centre of the bounding box, so a
//   scene offset by 1e6 loses no precision in differences. `slack` bounds the rounding error
//   of a projected coordinate (≤ 32 u Σ half-extents, u = 2^-24); cell ranges and the sweep
//   window are widened by it, which makes both conservative. The final decision is always the
//   shared predicate spheresOverlap() on the original coordinates, exactly as the oracle does.
// - Determinism. Keys are integers (cell, ordered z bits); the radix sort is stable with the
//   unsorted record number as value, so ties break by index. The sweep writes each record's
//   neighbours in a fixed order into fixed-size chunks whose concatenation does not depend on
//   how TBB schedules them. The covariance is summed in double in fixed chunks.
// - Once-only. Each record walks forwards through its cell and keeps a neighbour only in the
//   cell holding the lower corner of the two cell ranges' intersection (SPEC §3.7), so each
//   pair is found exactly once. The other side's view comes from a transpose: a stable radix
//   sort of (other particle, owner) by other particle. Both halves have a fixed order and
//   need no atomics.
#include "tumble/cpu/broadphase.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "grow.hpp"
#include "tumble/cpu/radix_sort.hpp"
#include "tumble/cpu/scan.hpp"
#include "tumble/error.hpp"
#include "tumble/memory.hpp"
#include "tumble/kernels/overlap.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble::cpu::detail {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

using namespace tumble::detail;  // kChunk (the fixed reduction chunk), the totals' limits (sweep_frame.hpp)

// The exact sum of n 32-bit counts (an integer sum: the same in any order).
std::uint64_t sum64(const std::uint32_t* c, std::uint32_t n) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, n, kChunk), std::uint64_t{0},
      [&](const auto& rg, std::uint64_t s) {
        for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) s += c[i];
        return s;
      },
      [](std::uint64_t a, std::uint64_t b) { return a + b; });
}

// The most candidate pairs the sweep may collect before it stops counting: the scans' limit, or
// fewer when the available memory (plus what the detection already holds) cannot take their
// buffers. The sweep stores its hits as it goes (4 bytes each), so without this bound 70 000
// coincident particles took 120 s and 10 GB before the count was refused.
std::uint64_t candidateBudget(std::uint64_t held) {
  const std::optional<std::uint64_t> have = availableMemory();
  if (!have) return kMaxEntries;
  const std::uint64_t fits = (*have + held * kCandidateBytes) / kCandidateBytes;
  return std::min(kMaxEntries, std::max(fits, (std::uint64_t{1} << 30) / kCandidateBytes));
}

constexpr std::uint32_t kSweepChunk = 2048;   // records per sweep output buffer

// The sweep's inner loop: tests `len` consecutive sorted records against one probe record and
// writes a 0/1 hit flag per candidate; returns the number of hits. Branch-free, so it vectorises; compiled twice (AVX2 and
// baseline x86-64) and picked at load time. Both clones do the same IEEE operations (no FMA:
// -ffp-contract=off), so the flags are identical.
struct Probe {
  float x, y, z, r, pz, window;
  std::uint32_t body;
  std::int32_t a0, b0, a, b;
};
struct SortedColumns {
  const float* x;
  const float* y;
  const float* z;
  const float* r;
  const float* pz;
  const std::uint32_t* body;
  const std::int32_t* a0;
  const std::int32_t* b0;
};

// GCC's ifunc resolver for target_clones runs before ThreadSanitizer's runtime is set up and
// crashes the process at start-up, so a TSan build has the baseline loop only (the same flags:
// both clones do the same IEEE operations).
#if defined(__SANITIZE_THREAD__)
#define TUMBLE_SWEEP_CLONES
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define TUMBLE_SWEEP_CLONES
#endif
#endif
#ifndef TUMBLE_SWEEP_CLONES
#define TUMBLE_SWEEP_CLONES __attribute__((target_clones("avx2", "default")))
#endif

TUMBLE_SWEEP_CLONES std::uint32_t testCandidates(const SortedColumns& c, std::uint32_t base,
                                                                    std::uint32_t len, const Probe& me,
                                                                    std::uint32_t* __restrict hits) {
  const float* __restrict cx = c.x + base;
  const float* __restrict cy = c.y + base;
  const float* __restrict cz = c.z + base;
  const float* __restrict cr = c.r + base;
  const float* __restrict cpz = c.pz + base;
  const std::uint32_t* __restrict cb = c.body + base;
  const std::int32_t* __restrict ca0 = c.a0 + base;
  const std::int32_t* __restrict cb0 = c.b0 + base;
  std::uint32_t numHits = 0;
  for (std::uint32_t t = 0; t < len; ++t) {
    const bool hit = (cpz[t] - me.pz < me.window) & (cb[t] != me.body) & (std::max(me.a0, ca0[t]) == me.a) &
                     (std::max(me.b0, cb0[t]) == me.b) & spheresOverlap(me.x, me.y, me.z, me.r, cx[t], cy[t], cz[t], cr[t]);
    hits[t] = hit;
    numHits += hit;
  }
  return numHits;
}

}  // namespace

void Broadphase::computeFrame(const BroadphaseInput& in, const BroadphaseParams& params) {
  using namespace tumble::detail;
  const std::uint32_t numChunks = (in.n + kChunk - 1) / kChunk;
  BoundsPartial* part = tumble::detail::grow(m_boundsPart, numChunks);
  tbb::parallel_for(std::uint32_t{0}, numChunks,
                    [&](std::uint32_t c) { part[c] = boundsOfRange(in, c * kChunk, std::min(in.n, (c + 1) * kChunk)); });
  const BoundsPartial b = combineBounds(part, numChunks);
  if (b.firstBad != 0xFFFFFFFFu)
    throw SimulationError("particle " + std::to_string(b.firstBad) + " has a non-finite position or radius",
                          b.firstBad);

  if (m_runsSinceAxis < 0 || m_runsSinceAxis >= std::max(1, params.pcaEvery)) {
    // Centred covariance (SPEC §3.1 fix) in double, per fixed chunk, shifted by particle 0 so
    // that the sums stay well conditioned; the chunks are combined in order.
    CovariancePartial* cov = tumble::detail::grow(m_covPart, numChunks);
    const double sx = in.x[0], sy = in.y[0], sz = in.z[0];
    tbb::parallel_for(std::uint32_t{0}, numChunks, [&](std::uint32_t c) {
      CovariancePartial a{};
      const std::uint32_t end = std::min(in.n, (c + 1) * kChunk);
      for (std::uint32_t i = c * kChunk; i < end; ++i) addCovariance(a.a, in.x[i], in.y[i], in.z[i], sx, sy, sz);
      cov[c] = a;
    });
    m_axis = principalAxisFromPartials(cov, numChunks, in.n);
    m_runsSinceAxis = 0;
  }
  ++m_runsSinceAxis;
  m_cellBits = tumble::detail::computeFrame(b, m_axis, in.maxRadius, in.cellRadius, params, &m_frame);
}

void Broadphase::run(const BroadphaseInput& in, const BroadphaseParams& params, double* seconds) {
  const std::uint32_t n = in.n;
  auto t0 = Clock::now();
  m_numRecords = 0;
  m_numEntries = 0;
  tumble::detail::grow(recFirst, n + 1);
  if (n == 0) {
    recFirst[0] = 0;
    tumble::detail::grow(nbrOffsets, 1)[0] = 0;
    return;
  }
  computeFrame(in, params);
  const SweepFrame f = m_frame;
  seconds[int(Phase::Axis)] += since(t0);

  // Keys: count records per particle, scan, emit (key, unsorted record number).
  t0 = Clock::now();
  ParticleRow* prow = tumble::detail::grow(m_prow, n);
  std::uint32_t* counts = tumble::detail::grow(m_counts, n + 1);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kChunk), [&](const auto& rg) {
    for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) countRecords(in, f, prow, counts, i);
  });
  counts[n] = 0;
  checkRecordTotal(sum64(counts, n), n, f.cellSize, in.maxRadius, kRecordBytes, m_keys.size());
  std::uint32_t* first = recFirst.data();
  std::size_t tempBytes = 0;
  exclusiveSum<std::uint32_t>(nullptr, tempBytes, counts, first, n + 1);
  exclusiveSum<std::uint32_t>(tumble::detail::grow(m_temp, tempBytes), tempBytes, counts, first, n + 1);
  const std::uint32_t numRec = first[n];
  m_numRecords = numRec;
  std::uint64_t* keys = tumble::detail::grow(m_keys, numRec);
  std::uint32_t* vals = tumble::detail::grow(m_vals, numRec);
  std::uint32_t* recParticle = tumble::detail::grow(m_recParticle, numRec);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kChunk), [&](const auto& rg) {
    for (std::uint32_t i = rg.begin(); i != rg.end(); ++i)
      emitRecords(in, f, prow, counts, first, keys, vals, recParticle, i);
  });
  seconds[int(Phase::Keys)] += since(t0);

  // Sort records by (cell, z).
  t0 = Clock::now();
  std::uint64_t* skeys = tumble::detail::grow(m_sortedKeys, numRec);
  std::uint32_t* svals = tumble::detail::grow(m_sortedVals, numRec);
  const int endBit = 32 + m_cellBits;
  radixSortPairs<std::uint64_t, std::uint32_t>(nullptr, tempBytes, keys, skeys, vals, svals, numRec, 0, endBit);
  radixSortPairs<std::uint64_t, std::uint32_t>(tumble::detail::grow(m_temp, tempBytes), tempBytes, keys, skeys,
                                               vals, svals, numRec, 0, endBit);
  seconds[int(Phase::Sort)] += since(t0);

  // Sweep: gather sorted columns, then walk each record's cell both ways.
  t0 = Clock::now();
  std::uint32_t* invp = tumble::detail::grow(inv, numRec);
  float* sx = tumble::detail::grow(m_sx, numRec);
  float* sy = tumble::detail::grow(m_sy, numRec);
  float* sz = tumble::detail::grow(m_sz, numRec);
  float* sr = tumble::detail::grow(m_sr, numRec);
  float* spz = tumble::detail::grow(m_spz, numRec);
  std::uint32_t* sp = tumble::detail::grow(m_sp, numRec);
  std::uint32_t* sbody = tumble::detail::grow(m_sbody, numRec);
  std::int32_t* sa0 = tumble::detail::grow(m_sa0, numRec);
  std::int32_t* sb0 = tumble::detail::grow(m_sb0, numRec);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, numRec, kChunk), [&](const auto& rg) {
    for (std::uint32_t s = rg.begin(); s != rg.end(); ++s) {
      const std::uint32_t r = svals[s];
      const std::uint32_t i = recParticle[r];
      const ParticleRow pi = prow[i];
      invp[r] = s;
      sp[s] = i;
      sx[s] = pi.x;
      sy[s] = pi.y;
      sz[s] = pi.z;
      sr[s] = pi.r;
      spz[s] = pi.pz;
      sbody[s] = pi.body;
      sa0[s] = pi.a0;
      sb0[s] = pi.b0;
    }
  });
  const std::uint32_t numChunks = (numRec + kSweepChunk - 1) / kSweepChunk;
  if (m_chunkNbr.size() < numChunks) m_chunkNbr.resize(numChunks);
  if (m_chunkHits.size() < numChunks) m_chunkHits.resize(numChunks);
  std::uint32_t* nbrCount = tumble::detail::grow(m_nbrCount, numRec + 1);
  const tumble::detail::SweepWindow win = tumble::detail::sweepWindow(in.maxRadius, f);
  const float reachR = win.reach;
  const float maxWindow = win.maxWindow;  // ≥ every record's window r_s + reachR
  const SortedColumns cols{sx, sy, sz, sr, spz, sbody, sa0, sb0};
  // Hits found so far, published every 2^16 per chunk (an integer count for the stop test only:
  // nothing of the result depends on it).
  const std::uint64_t budget = candidateBudget(nbr.size());
  std::atomic<std::uint64_t> found{0};
  std::atomic<bool> over{false};
  tbb::parallel_for(std::uint32_t{0}, numChunks, [&](std::uint32_t c) {
    auto& out = m_chunkNbr[c];
    out.clear();
    if (over.load(std::memory_order_relaxed)) return;
    std::uint64_t unpublished = 0;
    std::vector<std::uint32_t>& cand = m_chunkHits[c];  // kept between runs: no allocation once sized
    const std::uint32_t end = std::min(numRec, (c + 1) * kSweepChunk);
    std::uint32_t e = c * kSweepChunk + 1;  // two pointers: end of the widest possible window
    for (std::uint32_t s = c * kSweepChunk; s < end; ++s) {
      const std::uint32_t cell = static_cast<std::uint32_t>(skeys[s] >> 32);
      const float zs = spz[s];
      if (e <= s) e = s + 1;
      while (e < numRec && static_cast<std::uint32_t>(skeys[e] >> 32) == cell && spz[e] - zs < maxWindow) ++e;
      std::int32_t a, b;
      cellOfNumber(f, cell, &a, &b);
      const Probe me{sx[s], sy[s], sz[s], sr[s], zs, sr[s] + reachR, sbody[s], sa0[s], sb0[s], a, b};
      const std::uint32_t len = e - s - 1;
      if (cand.size() < len) cand.resize(len);
      const std::uint32_t base = s + 1;
      const std::uint32_t k = testCandidates(cols, base, len, me, cand.data());
      if (k > 0) {  // most records have no contact at all
        const std::uint32_t* hits = cand.data();
        for (std::uint32_t t = 0; t < len; ++t)
          if (hits[t]) out.push_back(sp[base + t]);
      }
      nbrCount[s] = k;
      unpublished += k;
      if (unpublished >= (1u << 16)) {
        if (found.fetch_add(unpublished, std::memory_order_relaxed) + unpublished > budget) {
          over.store(true, std::memory_order_relaxed);
          return;
        }
        unpublished = 0;
        if (over.load(std::memory_order_relaxed)) return;
      }
    }
    found.fetch_add(unpublished, std::memory_order_relaxed);
  });
  nbrCount[numRec] = 0;
  if (over.load() || found.load() > budget) {
    for (auto& v : m_chunkNbr) std::vector<std::uint32_t>().swap(v);  // give the hits back first
    checkTotal(budget, kMaxEntries, kCandidateBytes, nbr.size(), n, "candidate pairs", kDenseCause, /*atLeast=*/true);
  }
  checkTotal(sum64(nbrCount, numRec), kMaxEntries, kCandidateBytes, nbr.size(), n, "candidate pairs", kDenseCause);
  std::uint32_t* offs = tumble::detail::grow(nbrOffsets, numRec + 1);
  exclusiveSum<std::uint32_t>(nullptr, tempBytes, nbrCount, offs, numRec + 1);
  exclusiveSum<std::uint32_t>(tumble::detail::grow(m_temp, tempBytes), tempBytes, nbrCount, offs, numRec + 1);
  m_numEntries = offs[numRec];
  const std::uint32_t numEntries = static_cast<std::uint32_t>(m_numEntries);
  std::uint32_t* nb = tumble::detail::grow(nbr, numEntries);
  std::uint32_t* owner = tumble::detail::grow(m_owner, numEntries);
  tbb::parallel_for(std::uint32_t{0}, numChunks, [&](std::uint32_t c) {
    const auto& src = m_chunkNbr[c];
    std::copy(src.begin(), src.end(), nb + offs[c * kSweepChunk]);
    const std::uint32_t end = std::min(numRec, (c + 1) * kSweepChunk);
    for (std::uint32_t s = c * kSweepChunk; s < end; ++s)
      std::fill(owner + offs[s], owner + offs[s + 1], sp[s]);
  });
  // Transpose: stable sort of (other, owner) by other gives each particle its backward list.
  std::uint32_t* bkeys = tumble::detail::grow(m_backKeys, numEntries);
  std::uint32_t* bvals = tumble::detail::grow(back, numEntries);
  const int nBits = std::max(1, static_cast<int>(std::bit_width(n - 1)));
  radixSortPairs<std::uint32_t, std::uint32_t>(nullptr, tempBytes, nb, bkeys, owner, bvals, numEntries, 0, nBits);
  radixSortPairs<std::uint32_t, std::uint32_t>(tumble::detail::grow(m_temp, tempBytes), tempBytes, nb, bkeys, owner,
                                               bvals, numEntries, 0, nBits);
  // Offsets from the sorted keys: entry k starts particle i's list for every i in
  // (key[k−1], key[k]]; one writer per offset.
  std::uint32_t* boffs = tumble::detail::grow(backOffsets, n + 1);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, numEntries + 1, kChunk), [&](const auto& rg) {
    for (std::uint32_t k = rg.begin(); k != rg.end(); ++k) {
      const std::uint32_t lo = k == 0 ? 0 : bkeys[k - 1] + 1;
      const std::uint32_t hi = k == numEntries ? n : bkeys[k];
      for (std::uint32_t i = lo; i <= hi; ++i) boffs[i] = k;
    }
  });
  seconds[int(Phase::Sweep)] += since(t0);
}

std::vector<Pair> Broadphase::sortedPairs(std::uint32_t n) const {
  if (recFirst.size() < std::size_t(n) + 1 || m_numRecords == 0) return {};  // before the first detection
  return tumble::detail::sortedPairs(n, recFirst.data(), inv.data(), nbrOffsets.data(), nbr.data(), m_numEntries);
}

}  // namespace tumble::cpu::detail
