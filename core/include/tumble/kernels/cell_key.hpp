// SPDX-License-Identifier: MIT
/// @file cell_key.hpp
/// Sweep frame, 2-D subdivision and exact integer sort keys (SPEC §3.2–3.4).
///
/// Key layout (SPEC §3.4 fix): cell index in the bits above 32, the order-preserving image of
/// the float z in the low 32 bits. Integer keys sort identically on every backend; the report's
/// "float z + N·cell" loses the low bits of z once there are many cells.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>

#include "tumble/hd.hpp"
#include "tumble/math.hpp"

namespace tumble {

/// The frame of one detection: axes, origin, cells, and the rounding margin.
struct SweepFrame {
  Vec3f lp, lq, lz;       ///< orthonormal axes; lz is the sweep (PCA) axis
  Vec3f center;           ///< origin subtracted before projecting (exact for nearby points)
  float cellSize;         ///< M
  float invCellSize;      ///< 1 / M
  float slack;            ///< bound on the rounding error of a projected coordinate difference
  std::int32_t aMin, bMin;  ///< lowest cell indices that can occur
  std::uint32_t numA, numB; ///< cells along p and q
  std::uint32_t bShift;     ///< cell number = (a − aMin) << bShift | (b − bMin); 2^bShift ≥ numB
};

/// Order-preserving map float → uint32: a < b (as floats, not NaN) ⇔ bits(a) < bits(b).
/// Flips the sign bit of non-negative values and every bit of negative ones.
TUMBLE_HD_INLINE std::uint32_t orderedBits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

/// Inverse of orderedBits().
TUMBLE_HD_INLINE float fromOrderedBits(std::uint32_t u) {
  u = (u & 0x80000000u) ? (u & 0x7FFFFFFFu) : ~u;
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

/// Projected coordinates (p, q, z) of a point.
struct Projected {
  float p, q, z;
};

TUMBLE_HD_INLINE Projected project(const SweepFrame& f, Vec3f x) {
  const Vec3f d = x - f.center;
  return {dot(d, f.lp), dot(d, f.lq), dot(d, f.lz)};
}

/// Inclusive range of cells a particle's p–q square overlaps, widened by the rounding margin so
/// that it is conservative: two overlapping spheres always share at least one cell.
struct CellRange {
  std::int32_t a0, a1, b0, b1;
};

/// Clamped to [lo, lo + n − 1] before the conversion, in double (exact for every int32), so that
/// a product beyond the int32 range, infinite (a coordinate near the float limit) or NaN never
/// reaches the conversion, whose result would be undefined.
TUMBLE_HD_INLINE std::int32_t cellIndex(float v, float invCell, std::int32_t lo, std::uint32_t n) {
  const double c = static_cast<double>(std::floor(v * invCell));
  const std::int32_t hi = lo + static_cast<std::int32_t>(n) - 1;
  if (!(c > static_cast<double>(lo))) return lo;  // cannot happen inside the frame; float edge cases
  if (c >= static_cast<double>(hi)) return hi;
  return static_cast<std::int32_t>(c);
}

TUMBLE_HD_INLINE CellRange cellRange(const SweepFrame& f, Projected pr, float r) {
  const float e = r + f.slack;
  return {cellIndex(pr.p - e, f.invCellSize, f.aMin, f.numA), cellIndex(pr.p + e, f.invCellSize, f.aMin, f.numA),
          cellIndex(pr.q - e, f.invCellSize, f.bMin, f.numB), cellIndex(pr.q + e, f.invCellSize, f.bMin, f.numB)};
}

/// Cell number of cell (a, b): the b index in the low bShift bits, so that decoding a cell
/// number takes a shift and a mask rather than an integer division.
TUMBLE_HD_INLINE std::uint32_t cellNumber(const SweepFrame& f, std::int32_t a, std::int32_t b) {
  return (static_cast<std::uint32_t>(a - f.aMin) << f.bShift) | static_cast<std::uint32_t>(b - f.bMin);
}

/// Inverse of cellNumber().
TUMBLE_HD_INLINE void cellOfNumber(const SweepFrame& f, std::uint32_t cell, std::int32_t* outA, std::int32_t* outB) {
  *outA = static_cast<std::int32_t>(cell >> f.bShift) + f.aMin;
  *outB = static_cast<std::int32_t>(cell & ((1u << f.bShift) - 1u)) + f.bMin;
}

/// Sort key of a sweep record: cell number high, ordered z bits low.
TUMBLE_HD_INLINE std::uint64_t sweepKey(std::uint32_t cell, float z) {
  return (static_cast<std::uint64_t>(cell) << 32) | orderedBits(z);
}

/// Number of sweep records of a particle (cells its square overlaps).
/// (Saturates at 2^32 − 1, so that a huge range is refused by the caller's bound, never wraps.)
TUMBLE_HD_INLINE std::uint32_t numRecords(const CellRange& c) {
  const std::uint64_t k = std::uint64_t(std::uint32_t(c.a1 - c.a0 + 1)) * std::uint64_t(std::uint32_t(c.b1 - c.b0 + 1));
  return k < 0xffffffffull ? static_cast<std::uint32_t>(k) : 0xffffffffu;
}

/// Once-only rule (SPEC §3.7): a pair is reported only in the cell holding the lower corner of
/// the intersection of the two particles' cell ranges.
TUMBLE_HD_INLINE bool ownsPair(std::int32_t a, std::int32_t b, std::int32_t a0i, std::int32_t b0i, std::int32_t a0j,
                               std::int32_t b0j) {
  return (a0i > a0j ? a0i : a0j) == a && (b0i > b0j ? b0i : b0j) == b;
}

}  // namespace tumble
