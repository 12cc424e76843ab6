// SPDX-License-Identifier: MIT
// CUDA broadphase: the twin of cpu/src/broadphase.hpp (same stages, same CSR contact list,
// same bits). Internal to tumble::gpu.
#pragma once
#include <cstdint>
#include <vector>

#include "cuda_context.cuh"
#include "device_buffer.cuh"
#include "tumble/sweep_frame.hpp"
#include "tumble/kernels/cell_key.hpp"
#include "tumble/kernels/records.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene.hpp"

namespace tumble::gpu::detail {
using namespace tumble::detail;  // shared host-side frame logic (core/include/tumble/sweep_frame.hpp)
}  // namespace tumble::gpu::detail

namespace tumble::gpu::detail {

/// Finds every overlapping pair of particles of different bodies and stores them as the CPU's
/// CSR contact list in two halves, with identical contents:
/// - Forward: particle i's records are recFirst[i]..recFirst[i+1] (unsorted numbering), record r
///   sits at sorted position inv[r], and the neighbours it found walking forward are
///   nbr[nbrOffsets[s] .. nbrOffsets[s+1]).
/// - Backward: back[backOffsets[i] .. backOffsets[i+1]), the transpose in forward order.
class Broadphase {
 public:
  /// Runs the detection on ctx's stream. Throws tumble::SimulationError naming the lowest
  /// non-finite particle. With a timer, marks the Axis, Keys, Sort and Sweep phases.
  void run(const BroadphaseInput& in, const BroadphaseParams& params, const StreamContext& ctx, PhaseTimer* timer);
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
  std::vector<Pair> sortedPairs(std::uint32_t n, cudaStream_t stream) const;

  // CSR contact list on the device (valid after run()).
  DeviceBuffer<std::uint32_t> recFirst;     ///< n + 1
  DeviceBuffer<std::uint32_t> inv;          ///< unsorted record → sorted position
  DeviceBuffer<std::uint32_t> nbrOffsets;   ///< numRecords + 1
  DeviceBuffer<std::uint32_t> nbr;          ///< forward neighbour particle indices
  DeviceBuffer<std::uint32_t> backOffsets;  ///< n + 1
  DeviceBuffer<std::uint32_t> back;         ///< backward neighbour particle indices

 private:
  void computeFrame(const BroadphaseInput& in, const BroadphaseParams& params, const StreamContext& ctx);
  /// The 64-bit sum of n device counts (kChunk partials summed on the host; waits for them).
  std::uint64_t total(const std::uint32_t* counts, std::uint32_t n, const StreamContext& ctx);
  /// TUMBLE_VALIDATE builds: copies the run's arrays back and checks their invariants (sorted
  /// keys, monotone offsets, indices in range); throws tumble::Error naming the first violation.
  void validate(std::uint32_t n, cudaStream_t stream) const;

  SweepFrame m_frame{};
  Vec3f m_axis{0.0f, 0.0f, 1.0f};
  int m_runsSinceAxis = -1;
  std::uint32_t m_numRecords = 0;
  std::uint64_t m_numEntries = 0;
  int m_cellBits = 0;
  bool m_hasRun = false;

  // Scratch (grow-only).
  DeviceBuffer<BoundsPartial> m_boundsPart;
  DeviceBuffer<double> m_covPart;
  DeviceBuffer<unsigned long long> m_sumPart;
  std::vector<unsigned long long> m_hostSum;
  std::vector<BoundsPartial> m_hostBounds;
  std::vector<double> m_hostCov;
  DeviceBuffer<ParticleRow> m_prow;
  DeviceBuffer<std::uint32_t> m_counts;
  DeviceBuffer<std::uint64_t> m_keys, m_sortedKeys;
  DeviceBuffer<std::uint32_t> m_vals, m_sortedVals, m_recParticle;
  DeviceBuffer<unsigned char> m_temp;  // CUB temp storage, shared by every primitive
  DeviceBuffer<ParticleRow> m_srow;    // sorted-record rows (the CPU's sorted columns)
  DeviceBuffer<std::uint32_t> m_sp;    // sorted record → particle
  DeviceBuffer<std::uint32_t> m_nbrCount;
  DeviceBuffer<std::uint32_t> m_owner, m_backKeys;  // transpose input/output keys
};

}  // namespace tumble::gpu::detail
