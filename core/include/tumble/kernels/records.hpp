// SPDX-License-Identifier: MIT
/// @file records.hpp
/// Sweep records (SPEC §3.3–3.4): per-particle cell ranges and the (key, record) pairs to sort,
/// written once for both pipelines.
#pragma once
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/kernels/cell_key.hpp"

namespace tumble {

/// Particle columns the broadphase reads.
struct BroadphaseInput {
  const float* x;
  const float* y;
  const float* z;
  const float* r;
  const std::uint32_t* body;
  std::uint32_t n;
  float maxRadius;
  /// The radius the automatic cell size is sized from (sizingRadius() of the radii): 0 means
  /// maxRadius. Speed only: any cell size gives the same pairs.
  float cellRadius = 0.0f;
};

/// One particle's row, written by the key count pass and gathered per sorted record: one
/// 32-byte load per record instead of eight scattered columns.
struct alignas(32) ParticleRow {
  float x, y, z, r, pz;
  std::uint32_t body;
  std::int32_t a0, b0;
};

/// Count pass for particle i: its row and its number of records (cells overlapped).
TUMBLE_HD_INLINE void countRecords(const BroadphaseInput& in, const SweepFrame& f, ParticleRow* prow,
                                   std::uint32_t* counts, std::uint32_t i) {
  const Projected pr = project(f, Vec3f{in.x[i], in.y[i], in.z[i]});
  const CellRange cr = cellRange(f, pr, in.r[i]);
  prow[i] = ParticleRow{in.x[i], in.y[i], in.z[i], in.r[i], pr.z, in.body[i], cr.a0, cr.b0};
  counts[i] = numRecords(cr);
}

/// Emit pass for particle i: its records from first[i] on, in (a, b) row-major order, with key
/// (cell, z) and value = the unsorted record number.
TUMBLE_HD_INLINE void emitRecords(const BroadphaseInput& in, const SweepFrame& f, const ParticleRow* prow,
                                  const std::uint32_t* counts, const std::uint32_t* first, std::uint64_t* keys,
                                  std::uint32_t* vals, std::uint32_t* recParticle, std::uint32_t i) {
  std::uint32_t r = first[i];
  const ParticleRow pi = prow[i];
  if (counts[i] == 1) {
    keys[r] = sweepKey(cellNumber(f, pi.a0, pi.b0), pi.pz);
    vals[r] = r;
    recParticle[r] = i;
    return;
  }
  // Same float expressions as countRecords(), so the same range; `end` guards the slot anyway.
  const std::uint32_t end = first[i + 1];
  const CellRange cr = cellRange(f, project(f, Vec3f{in.x[i], in.y[i], in.z[i]}), in.r[i]);
  for (std::int32_t a = cr.a0; a <= cr.a1; ++a)
    for (std::int32_t b = cr.b0; b <= cr.b1 && r < end; ++b, ++r) {
      keys[r] = sweepKey(cellNumber(f, a, b), pi.pz);
      vals[r] = r;
      recParticle[r] = i;
    }
}

}  // namespace tumble
