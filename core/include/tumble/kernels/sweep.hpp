// SPDX-License-Identifier: MIT
/// @file sweep.hpp
/// The CUDA broadphase's per-element steps after the sort (SPEC §3.5–3.7), written once here so
/// that the CPU runs and tests them too (validation/tests/shared_gpu_logic_test.cpp runs the
/// CUDA broadphase's stage list on the CPU with these functions and compares every array with the
/// CPU broadphase's): the gather of a sorted record, the sweep of one record (count or emit),
/// and the offsets of the transposed list by binary search. The CPU broadphase sweeps with its
/// own vectorised loop (cpu/src/broadphase.cpp, testCandidates) over the same predicate.
#pragma once
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/kernels/cell_key.hpp"
#include "tumble/kernels/overlap.hpp"
#include "tumble/kernels/records.hpp"

namespace tumble {

/// Sorted position s of the records: record r = svals[s] of particle i gets inv[r] = s, and
/// position s the particle and its row (one 32-byte row per record instead of eight columns).
TUMBLE_HD_INLINE void gatherRecord(const std::uint32_t* svals, const std::uint32_t* recParticle,
                                   const ParticleRow* prow, std::uint32_t s, std::uint32_t* inv, std::uint32_t* sp,
                                   ParticleRow* srow) {
  const std::uint32_t r = svals[s];
  const std::uint32_t i = recParticle[r];
  inv[r] = s;
  sp[s] = i;
  srow[s] = prow[i];
}

/// What a sweep reads: the sorted keys, rows and particles, and the window constants
/// (detail::sweepWindow: reach = maxRadius + 2 slack, maxWindow = 2 reach).
struct SweepRecords {
  const std::uint64_t* skeys;
  const ParticleRow* srow;
  const std::uint32_t* sp;
  std::uint32_t numRec;
  SweepFrame frame;
  float reach;
  float maxWindow;
};

/// The sweep of sorted record s: walks forward through its cell and counts (kEmit = false) or
/// writes from nbr[base] on, with owner[] = its particle (kEmit = true), the hits in candidate
/// order. The CPU's sweep bounds each record's run by the widest window (maxWindow, two pointers)
/// and tests the record's own window r_s + reach per candidate. Along a cell the records are
/// sorted by z and fl(z_t − z_s) is monotone in z_t, so once a candidate fails the record's own
/// window every later one fails it too: breaking there drops only candidates the CPU rejects, and
/// the hits and their order are the CPU's. Returns the number of hits.
template <bool kEmit>
TUMBLE_HD_INLINE std::uint32_t sweepRecord(const SweepRecords& a, std::uint32_t s, std::uint32_t* nbr,
                                           std::uint32_t* owner, std::uint32_t base) {
  const std::uint32_t cell = static_cast<std::uint32_t>(a.skeys[s] >> 32);
  const ParticleRow me = a.srow[s];
  std::int32_t ca, cb;
  cellOfNumber(a.frame, cell, &ca, &cb);
  const float window = me.r + a.reach;
  const std::uint32_t self = kEmit ? a.sp[s] : 0u;
  std::uint32_t k = 0;
  for (std::uint32_t t = s + 1; t < a.numRec; ++t) {
    if (static_cast<std::uint32_t>(a.skeys[t] >> 32) != cell) break;  // the CPU's two-pointer bound …
    const ParticleRow c = a.srow[t];
    if (!(c.pz - me.pz < a.maxWindow)) break;                          // … (same cell, z within maxWindow)
    if (!(c.pz - me.pz < window)) break;  // exact early exit (above)
    if (c.body != me.body && ownsPair(ca, cb, me.a0, me.b0, c.a0, c.b0) &&
        spheresOverlap(me.x, me.y, me.z, me.r, c.x, c.y, c.z, c.r)) {
      if constexpr (kEmit) {
        nbr[base + k] = a.sp[t];
        owner[base + k] = self;
      }
      ++k;
    }
  }
  return k;
}

/// The first k in [0, n) with keys[k] ≥ v (n if none), keys ascending: the transposed list's
/// offset of particle v (backOffsets[v]), one writer per offset. The CPU fills the same offsets
/// per entry instead.
TUMBLE_HD_INLINE std::uint32_t lowerBound(const std::uint32_t* keys, std::uint32_t n, std::uint32_t v) {
  std::uint32_t lo = 0, hi = n;
  while (lo < hi) {
    const std::uint32_t mid = lo + (hi - lo) / 2;
    if (keys[mid] < v)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

}  // namespace tumble
