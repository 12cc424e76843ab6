// SPDX-License-Identifier: MIT
// The CUDA pipeline's broadphase (SPEC §3), written once over the execution layer (exec/exec.hpp)
// and compiled for the device (CudaExec, nvcc) and for the host backend (HostExec, g++). The
// stage-by-stage twin of cpu/src/broadphase.cpp: same stages, same CSR contact list, same bits.
// Internal to tumble::gpu.
//
// Design notes
// - Same bits as the CPU. Every per-element step is a shared TUMBLE_HD function of core/
//   (countRecords, emitRecords, addParticle/mergeBounds, addCovariance: the CPU calls them too;
//   gatherRecord, sweepRecord, lowerBound: sweep_frame.hpp and kernels/sweep.hpp), called from
//   the functors below. The radix sorts are stable sorts over the same bit ranges as the CPU's,
//   with the unsorted record number as value, so the permutation is unique; with --fmad=false
//   (TUMBLE_STRICT_FP) every key, every sorted position and every pair is the same.
// - Bounds and covariance: reductions over the CPU's fixed 4096-particle chunks (kChunk), each
//   chunk folded in index order (exec.hpp), the partials combined on the host in chunk order and
//   the axis solved there by the same Eigen code (core/src/sweep_frame.cpp). The covariance runs
//   only when the axis is due (every pcaEvery runs).
// - Output capacity. The CPU's sweep appends into fixed-size chunk buffers; here the sweep runs
//   twice instead, count → exclusive scan → emit (STYLE §5), which yields the same nbrOffsets and
//   nbr arrays with no atomics and no overflow path. The totals are summed in 64 bits first and
//   refused beyond the 32-bit scans (checkTotal). The transpose is a stable sort of (other, owner)
//   by other, like the CPU's.
// - Host round trips per run: the bounds (and covariance) partials, the record total and the
//   candidate total.
#pragma once
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "exec/exec.hpp"
#include "tumble/config.hpp"
#include "tumble/error.hpp"
#include "tumble/kernels/cell_key.hpp"
#include "tumble/kernels/records.hpp"
#include "tumble/kernels/sweep.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble::gpu::detail {
inline namespace TUMBLE_EXEC_ABI {  // one copy per compiler (exec.hpp)

using tumble::detail::BoundsPartial;
using tumble::detail::CovariancePartial;
using tumble::detail::kChunk;

// --- Reductions (exec.hpp's op contract) ---------------------------------------------------

/// The bounds of the finite particles and the lowest non-finite one: exact in any grouping.
struct BoundsOp {
  BroadphaseInput in;
  using Value = BoundsPartial;
  static constexpr bool kAnyGrouping = true;
  TUMBLE_HD Value identity() const { return tumble::detail::emptyBounds(); }
  TUMBLE_HD void add(Value& b, std::uint32_t i) const { tumble::detail::addParticle(b, i, in.x[i], in.y[i], in.z[i], in.r[i]); }
  TUMBLE_HD void merge(Value& left, const Value& right) const { tumble::detail::mergeBounds(left, right); }
};

/// The covariance sums in double, shifted by particle 0 (the CPU's per-chunk loop): a float sum,
/// folded in index order.
struct CovarianceOp {
  BroadphaseInput in;
  using Value = CovariancePartial;
  static constexpr bool kAnyGrouping = false;
  TUMBLE_HD Value identity() const { return Value{{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0}}; }
  TUMBLE_HD void add(Value& a, std::uint32_t i) const {
    tumble::detail::addCovariance(a.a, in.x[i], in.y[i], in.z[i], in.x[0], in.y[0], in.z[0]);
  }
  TUMBLE_HD void merge(Value&, const Value&) const {}  // not used: kAnyGrouping is false
};

/// The 64-bit sum of 32-bit counts (integers: exact in any grouping).
struct CountSumOp {
  const std::uint32_t* counts;
  using Value = unsigned long long;
  static constexpr bool kAnyGrouping = true;
  TUMBLE_HD Value identity() const { return 0ull; }
  TUMBLE_HD void add(Value& s, std::uint32_t i) const { s += counts[i]; }
  TUMBLE_HD void merge(Value& left, const Value& right) const { left += right; }
};

// --- Per-element functors ------------------------------------------------------------------

// The CPU's first key loop; element n writes the trailing zero of counts.
struct KeysCountFn {
  BroadphaseInput in;
  SweepFrame f;
  ParticleRow* prow;
  std::uint32_t* counts;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    if (i < in.n) countRecords(in, f, prow, counts, i);
    else counts[i] = 0;
  }
};

// The CPU's second key loop: particle i's records in (a, b) row-major order.
struct KeysEmitFn {
  BroadphaseInput in;
  SweepFrame f;
  const ParticleRow* prow;
  const std::uint32_t* counts;
  const std::uint32_t* first;
  std::uint64_t* keys;
  std::uint32_t* vals;
  std::uint32_t* recParticle;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    emitRecords(in, f, prow, counts, first, keys, vals, recParticle, i);
  }
};

struct GatherFn {
  const std::uint32_t* svals;
  const std::uint32_t* recParticle;
  const ParticleRow* prow;
  std::uint32_t* inv;
  std::uint32_t* sp;
  ParticleRow* srow;
  TUMBLE_HD void operator()(std::uint32_t s) const { gatherRecord(svals, recParticle, prow, s, inv, sp, srow); }
};

// The sweep's count pass (sweepRecord); element numRec writes the trailing zero.
struct SweepCountFn {
  SweepRecords a;
  std::uint32_t* nbrCount;
  TUMBLE_HD void operator()(std::uint32_t s) const {
    nbrCount[s] = s == a.numRec ? 0u : sweepRecord<false>(a, s, nullptr, nullptr, 0u);
  }
};

// The emit pass: the same walk, writing at the scanned offsets (one writer per entry).
struct SweepEmitFn {
  SweepRecords a;
  const std::uint32_t* nbrOffsets;
  std::uint32_t* nbr;
  std::uint32_t* owner;
  TUMBLE_HD void operator()(std::uint32_t s) const {
    const std::uint32_t base = nbrOffsets[s];
    if (nbrOffsets[s + 1] == base) return;  // most records have no contact at all
    sweepRecord<true>(a, s, nbr, owner, base);
  }
};

// backOffsets[i] = lowerBound(bkeys, numEntries, i): one writer per offset.
struct BackOffsetsFn {
  const std::uint32_t* bkeys;
  std::uint32_t numEntries;
  std::uint32_t* backOffsets;
  TUMBLE_HD void operator()(std::uint32_t i) const { backOffsets[i] = lowerBound(bkeys, numEntries, i); }
};

/// The 64-bit total of n device counts: kChunk partials summed on the host (waits for them).
template <class Exec>
std::uint64_t countTotal(const std::uint32_t* counts, std::uint32_t n, const typename Exec::Stream& s,
                         typename Exec::template Buffer<unsigned long long>& part,
                         std::vector<unsigned long long>& host) {
  const std::uint32_t numChunks = (n + kChunk - 1) / kChunk;
  if (numChunks == 0) return 0;
  Exec::reduceChunks(s, n, kChunk, CountSumOp{counts}, part.grow(numChunks), "countTotal");
  host.resize(numChunks);
  part.download(host.data(), numChunks, s);
  s.synchronize();
  std::uint64_t total = 0;
  for (unsigned long long v : host) total += v;
  return total;
}

/// Finds every overlapping pair of particles of different bodies and stores them as the CPU's
/// CSR contact list in two halves, with identical contents:
/// - Forward: particle i's records are recFirst[i]..recFirst[i+1] (unsorted numbering), record r
///   sits at sorted position inv[r], and the neighbours it found walking forward are
///   nbr[nbrOffsets[s] .. nbrOffsets[s+1]).
/// - Backward: back[backOffsets[i] .. backOffsets[i+1]), the transpose in forward order.
template <class Exec>
class Broadphase {
 public:
  using Stream = typename Exec::Stream;
  template <class T>
  using Buffer = typename Exec::template Buffer<T>;

  /// Runs the detection on stream s. Throws tumble::SimulationError naming the lowest non-finite
  /// particle. With a timer, marks the Axis, Keys, Sort and Sweep phases.
  void run(const BroadphaseInput& in, const BroadphaseParams& params, const Stream& s,
           typename Exec::Timer* timer) {
    const std::uint32_t n = in.n;
    m_numRecords = 0;
    m_numEntries = 0;
    m_hasRun = false;
    if (timer != nullptr) timer->mark(Phase::Axis, s);
    if (n == 0) {
      Exec::fillZero(s, recFirst.grow(1), 1);
      Exec::fillZero(s, nbrOffsets.grow(1), 1);
      Exec::fillZero(s, backOffsets.grow(1), 1);
      if (timer != nullptr)
        for (Phase p : {Phase::Keys, Phase::Sort, Phase::Sweep}) timer->mark(p, s);
      m_hasRun = true;
      return;
    }
    computeFrame(in, params, s);
    const SweepFrame f = m_frame;

    // Keys: count records per particle, scan, emit (key, unsorted record number).
    if (timer != nullptr) timer->mark(Phase::Keys, s);
    ParticleRow* prow = m_prow.grow(n);
    std::uint32_t* counts = m_counts.grow(std::size_t(n) + 1);
    std::uint32_t* first = recFirst.grow(std::size_t(n) + 1);
    Exec::forEach(s, std::uint64_t(n) + 1, KeysCountFn{in, f, prow, counts}, "keysCount");
    // The total in 64 bits before the 32-bit scan (it is also the scan's last offset, so it is
    // the only read-back here).
    const std::uint64_t numRec64 = countTotal<Exec>(counts, n, s, m_sumPart, m_hostSum);
    tumble::detail::checkRecordTotal(numRec64, n, f.cellSize, in.maxRadius, 0, 0);
    Exec::exclusiveSum(s, m_temp, counts, first, n + 1);
    const auto numRec = static_cast<std::uint32_t>(numRec64);
    m_numRecords = numRec;
    std::uint64_t* keys = m_keys.grow(numRec);
    std::uint32_t* vals = m_vals.grow(numRec);
    std::uint32_t* recParticle = m_recParticle.grow(numRec);
    Exec::forEach(s, n, KeysEmitFn{in, f, prow, counts, first, keys, vals, recParticle}, "keysEmit");

    // Sort records by (cell, z): stable, bits [0, 32 + cellBits), as the CPU.
    if (timer != nullptr) timer->mark(Phase::Sort, s);
    std::uint64_t* skeys = m_sortedKeys.grow(numRec);
    std::uint32_t* svals = m_sortedVals.grow(numRec);
    Exec::radixSortPairs(s, m_temp, keys, skeys, vals, svals, numRec, 0, 32 + m_cellBits);

    // Sweep: gather sorted rows, count, scan, emit; then the transpose.
    if (timer != nullptr) timer->mark(Phase::Sweep, s);
    std::uint32_t* invp = inv.grow(numRec);
    std::uint32_t* sp = m_sp.grow(numRec);
    ParticleRow* srow = m_srow.grow(numRec);
    Exec::forEach(s, numRec, GatherFn{svals, recParticle, prow, invp, sp, srow}, "gather");
    const tumble::detail::SweepWindow w = tumble::detail::sweepWindow(in.maxRadius, f);
    const SweepRecords args{skeys, srow, sp, numRec, f, w.reach, w.maxWindow};
    std::uint32_t* nbrCount = m_nbrCount.grow(std::size_t(numRec) + 1);
    Exec::forEach(s, std::uint64_t(numRec) + 1, SweepCountFn{args, nbrCount}, "sweepCount");
    const std::uint64_t numEntries64 = countTotal<Exec>(nbrCount, numRec, s, m_sumPart, m_hostSum);
    tumble::detail::checkTotal(numEntries64, tumble::detail::kMaxEntries, 0, 0, n, "candidate pairs",
                               tumble::detail::kDenseCause);
    std::uint32_t* offs = nbrOffsets.grow(std::size_t(numRec) + 1);
    Exec::exclusiveSum(s, m_temp, nbrCount, offs, numRec + 1);
    const auto numEntries = static_cast<std::uint32_t>(numEntries64);
    m_numEntries = numEntries;
    std::uint32_t* nb = nbr.grow(numEntries);
    std::uint32_t* owner = m_owner.grow(numEntries);
    std::uint32_t* bkeys = m_backKeys.grow(numEntries);
    std::uint32_t* bvals = back.grow(numEntries);
    if (numEntries > 0) {
      Exec::forEach(s, numRec, SweepEmitFn{args, offs, nb, owner}, "sweepEmit");
      // Transpose: stable sort of (other, owner) by other over bits [0, bit_width(n − 1)).
      int nBits = 1;
      while (nBits < 32 && ((n - 1) >> nBits) != 0) ++nBits;  // max(1, std::bit_width(n − 1))
      Exec::radixSortPairs(s, m_temp, nb, bkeys, owner, bvals, numEntries, 0, nBits);
    }
    Exec::forEach(s, std::uint64_t(n) + 1, BackOffsetsFn{bkeys, numEntries, backOffsets.grow(std::size_t(n) + 1)},
                  "backOffsets");
    m_hasRun = true;
#if TUMBLE_VALIDATE
    validate(n, s);
#endif
  }

  /// Forces the next run to recompute the PCA axis and forgets the last result.
  void reset() {
    m_runsSinceAxis = -1;
    m_hasRun = false;
    m_numRecords = 0;
    m_numEntries = 0;
  }

  bool hasRun() const { return m_hasRun; }
  std::uint32_t numRecords() const { return m_numRecords; }
  std::uint64_t numPairs() const { return m_numEntries; }
  std::uint64_t numCells() const { return std::uint64_t(m_frame.numA) * m_frame.numB; }
  const SweepFrame& frame() const { return m_frame; }

  /// Pairs (i < j), sorted: copies the forward half back and sorts it like the CPU.
  std::vector<Pair> sortedPairs(std::uint32_t n, const Stream& s) const {
    if (!m_hasRun) return {};
    std::vector<std::uint32_t> hFirst(std::size_t(n) + 1), hInv(m_numRecords),
        hOffs(std::size_t(m_numRecords) + 1), hNbr(m_numEntries);
    recFirst.download(hFirst.data(), hFirst.size(), s);
    inv.download(hInv.data(), hInv.size(), s);
    nbrOffsets.download(hOffs.data(), hOffs.size(), s);
    nbr.download(hNbr.data(), hNbr.size(), s);
    s.synchronize();
    return tumble::detail::sortedPairs(n, hFirst.data(), hInv.data(), hOffs.data(), hNbr.data(), m_numEntries);
  }

  /// The sweep's lists as the rows read them (kernels/contact_list.hpp; valid after run()).
  SweepListView listView() const {
    return {recFirst.data(), inv.data(), nbrOffsets.data(), nbr.data(), backOffsets.data(), back.data()};
  }

  // CSR contact list in the backend's memory (valid after run()).
  Buffer<std::uint32_t> recFirst;     ///< n + 1
  Buffer<std::uint32_t> inv;          ///< unsorted record → sorted position
  Buffer<std::uint32_t> nbrOffsets;   ///< numRecords + 1
  Buffer<std::uint32_t> nbr;          ///< forward neighbour particle indices
  Buffer<std::uint32_t> backOffsets;  ///< n + 1
  Buffer<std::uint32_t> back;         ///< backward neighbour particle indices

 private:
  // The bounds (and, when the axis is due, the covariance) of the input, then the frame.
  void computeFrame(const BroadphaseInput& in, const BroadphaseParams& params, const Stream& s) {
    const std::uint32_t numChunks = (in.n + kChunk - 1) / kChunk;
    Exec::reduceChunks(s, in.n, kChunk, BoundsOp{in}, m_boundsPart.grow(numChunks), "bounds");
    const bool newAxis = m_runsSinceAxis < 0 || m_runsSinceAxis >= std::max(1, params.pcaEvery);
    // Queued before the bounds are checked, to save a round trip; with a non-finite particle
    // its result is discarded (the CPU computes it only after the check; same observable result).
    const bool covariance = newAxis && in.n >= 2;
    if (covariance) Exec::reduceChunks(s, in.n, kChunk, CovarianceOp{in}, m_covPart.grow(numChunks), "covariance");
    m_hostBounds.resize(numChunks);
    m_boundsPart.download(m_hostBounds.data(), numChunks, s);
    if (covariance) {
      m_hostCov.resize(numChunks);
      m_covPart.download(m_hostCov.data(), numChunks, s);
    }
    s.synchronize();

    const BoundsPartial b = tumble::detail::combineBounds(m_hostBounds.data(), numChunks);
    if (b.firstBad != 0xFFFFFFFFu)
      throw SimulationError("particle " + std::to_string(b.firstBad) + " has a non-finite position or radius",
                            b.firstBad);
    if (newAxis) {
      m_axis = covariance ? tumble::detail::principalAxisFromPartials(m_hostCov.data(), numChunks, in.n)
                          : Vec3f{0.0f, 0.0f, 1.0f};
      m_runsSinceAxis = 0;
    }
    ++m_runsSinceAxis;
    m_cellBits = tumble::detail::computeFrame(b, m_axis, in.maxRadius, in.cellRadius, params, &m_frame);
  }

  /// TUMBLE_VALIDATE builds: copies the run's arrays back and checks their invariants (sorted
  /// keys, monotone offsets, indices in range); throws tumble::Error naming the first violation.
  void validate(std::uint32_t n, const Stream& s) const {
    const std::uint32_t numRec = m_numRecords;
    const auto numEntries = static_cast<std::uint32_t>(m_numEntries);
    std::vector<std::uint64_t> skeys(numRec);
    std::vector<std::uint32_t> first(std::size_t(n) + 1), invh(numRec), offs(std::size_t(numRec) + 1),
        nb(numEntries), bkeys(numEntries), bvals(numEntries), boffs(std::size_t(n) + 1);
    m_sortedKeys.download(skeys.data(), skeys.size(), s);
    recFirst.download(first.data(), first.size(), s);
    inv.download(invh.data(), invh.size(), s);
    nbrOffsets.download(offs.data(), offs.size(), s);
    nbr.download(nb.data(), nb.size(), s);
    m_backKeys.download(bkeys.data(), bkeys.size(), s);
    back.download(bvals.data(), bvals.size(), s);
    backOffsets.download(boffs.data(), boffs.size(), s);
    s.synchronize();
    auto fail = [](const std::string& what) { throw Error("TUMBLE_VALIDATE (CUDA broadphase): " + what); };
    if (first[0] != 0 || first[n] != numRec) fail("recFirst does not span the records");
    for (std::uint32_t i = 0; i < n; ++i)
      if (first[i + 1] <= first[i]) fail("particle " + std::to_string(i) + " has no record");
    for (std::uint32_t r = 1; r < numRec; ++r)
      if (skeys[r] < skeys[r - 1]) fail("sort keys not sorted at " + std::to_string(r));
    std::vector<char> seen(numRec, 0);
    for (std::uint32_t r = 0; r < numRec; ++r) {
      if (invh[r] >= numRec || seen[invh[r]]) fail("inv is not a permutation at record " + std::to_string(r));
      seen[invh[r]] = 1;
    }
    if (offs[0] != 0 || offs[numRec] != numEntries) fail("nbrOffsets does not span the entries");
    for (std::uint32_t r = 0; r < numRec; ++r)
      if (offs[r + 1] < offs[r]) fail("nbrOffsets decreases at " + std::to_string(r));
    for (std::uint32_t e = 0; e < numEntries; ++e) {
      if (nb[e] >= n || bvals[e] >= n) fail("entry " + std::to_string(e) + " names a particle out of range");
      if (e > 0 && bkeys[e] < bkeys[e - 1]) fail("transpose keys not sorted at " + std::to_string(e));
    }
    if (boffs[0] != 0 || boffs[n] != numEntries) fail("backOffsets does not span the entries");
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t e = boffs[i]; e < boffs[i + 1]; ++e)
        if (bkeys[e] != i) fail("backOffsets of particle " + std::to_string(i) + " are wrong");
  }

  SweepFrame m_frame{};
  Vec3f m_axis{0.0f, 0.0f, 1.0f};
  int m_runsSinceAxis = -1;
  std::uint32_t m_numRecords = 0;
  std::uint64_t m_numEntries = 0;
  int m_cellBits = 0;
  bool m_hasRun = false;

  // Scratch (grow-only).
  Buffer<BoundsPartial> m_boundsPart;
  Buffer<CovariancePartial> m_covPart;
  Buffer<unsigned long long> m_sumPart;
  std::vector<unsigned long long> m_hostSum;
  std::vector<BoundsPartial> m_hostBounds;
  std::vector<CovariancePartial> m_hostCov;
  Buffer<ParticleRow> m_prow;
  Buffer<std::uint32_t> m_counts;
  Buffer<std::uint64_t> m_keys, m_sortedKeys;
  Buffer<std::uint32_t> m_vals, m_sortedVals, m_recParticle;
  Buffer<unsigned char> m_temp;    // sort and scan temp storage, shared by every primitive
  Buffer<ParticleRow> m_srow;      // sorted-record rows (the CPU's sorted columns)
  Buffer<std::uint32_t> m_sp;      // sorted record → particle
  Buffer<std::uint32_t> m_nbrCount;
  Buffer<std::uint32_t> m_owner, m_backKeys;  // transpose input/output keys
};

}  // namespace TUMBLE_EXEC_ABI
}  // namespace tumble::gpu::detail
