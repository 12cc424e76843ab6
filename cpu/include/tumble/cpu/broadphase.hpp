// SPDX-License-Identifier: MIT
// CPU broadphase: sweep and prune along the PCA axis with 2-D subdivision (SPEC §3). The CPU
// pipeline's detection stage (namespace detail: no stable API), in the public headers so that
// the CUDA broadphase's tests (gpu/tests/cuda_host_broadphase_test.cpp) compare with it array by
// array without reaching into cpu/src.
#pragma once
#include <cstdint>
#include <vector>

#include "tumble/kernels/cell_key.hpp"
#include "tumble/kernels/records.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble::cpu::detail {

/// Finds every overlapping pair of particles of different bodies and stores them as a CSR
/// contact list in two halves.
/// - Forward: particle i's records are recFirst[i]..recFirst[i+1] (unsorted numbering), record r
///   sits at sorted position inv[r], and the neighbours it found walking forward are
///   nbr[nbrOffsets[s] .. nbrOffsets[s+1]). Each pair is found once, by the earlier record.
/// - Backward: the same pairs seen from the other side, back[backOffsets[i] .. backOffsets[i+1]),
///   in the order the forward half lists them (a stable radix sort by particle: the transpose).
/// Together they list every neighbour of i exactly once, in an order fixed by the input.
class Broadphase {
 public:
  /// Runs the detection. Throws tumble::Error (with `what` as context) on a non-finite coordinate.
  /// seconds[] receives the Axis, Keys, Sort and Sweep phase times (added).
  void run(const BroadphaseInput& in, const BroadphaseParams& params, double* seconds);
  /// Forces the next run to recompute the PCA axis.
  void invalidateAxis() { m_runsSinceAxis = -1; }

  std::uint32_t numRecords() const { return m_numRecords; }
  std::uint64_t numPairs() const { return m_numEntries; }
  std::uint64_t numCells() const { return std::uint64_t(m_frame.numA) * m_frame.numB; }  ///< cells of the grid
  const SweepFrame& frame() const { return m_frame; }
  /// Pairs (i < j), sorted.
  std::vector<Pair> sortedPairs(std::uint32_t n) const;

  // CSR contact list (valid after run()).
  std::vector<std::uint32_t> recFirst;    ///< n + 1
  std::vector<std::uint32_t> inv;         ///< unsorted record → sorted position
  std::vector<std::uint32_t> nbrOffsets;  ///< numRecords + 1
  std::vector<std::uint32_t> nbr;         ///< forward neighbour particle indices
  std::vector<std::uint32_t> backOffsets; ///< n + 1
  std::vector<std::uint32_t> back;        ///< backward neighbour particle indices

 private:
  void computeFrame(const BroadphaseInput& in, const BroadphaseParams& params);

  SweepFrame m_frame{};
  Vec3f m_axis{0.0f, 0.0f, 1.0f};
  int m_runsSinceAxis = -1;
  std::uint32_t m_numRecords = 0;
  std::uint64_t m_numEntries = 0;
  int m_cellBits = 0;

  // Scratch (grow-only).
  std::vector<ParticleRow> m_prow;
  std::vector<std::uint32_t> m_counts;
  std::vector<std::uint64_t> m_keys, m_sortedKeys;
  std::vector<std::uint32_t> m_vals, m_sortedVals, m_recParticle;
  std::vector<std::byte> m_temp;
  std::vector<tumble::detail::BoundsPartial> m_boundsPart;
  std::vector<tumble::detail::CovariancePartial> m_covPart;
  // Sorted-record columns: the sweep reads contiguous runs of them (branch-free, vectorisable).
  std::vector<float> m_sx, m_sy, m_sz, m_sr, m_spz;
  std::vector<std::uint32_t> m_sp, m_sbody;
  std::vector<std::int32_t> m_sa0, m_sb0;
  std::vector<std::uint32_t> m_nbrCount;
  std::vector<std::uint32_t> m_owner, m_backKeys;  // transpose input: (other, owner) per pair
  std::vector<std::vector<std::uint32_t>> m_chunkNbr, m_chunkHits;
};

}  // namespace tumble::cpu::detail
