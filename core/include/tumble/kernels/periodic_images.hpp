// SPDX-License-Identifier: MIT
/// @file periodic_images.hpp
/// Detection in a periodic box (docs/model.md#periodic-boundaries), per element, for both
/// pipelines. The sweep knows nothing of the boundaries: it runs on the particles with their
/// periodic coordinates wrapped into the box [−h, h), plus ghost images of those near the box's
/// lower ends, and each particle's candidate row gathers what it and its ghosts found, as
/// particles, each partner once. Three count → scan → fill steps at a rebuild:
///   1. wrapImage() per particle (its wrapped coordinates, its number of ghosts); scan → ghostFirst;
///      writeGhosts() per particle (its ghosts at sweep indices n + ghostFirst[i] ..).
///   2. the sweep over the n + ghosts images (BroadphaseInput of those columns).
///   3. periodicRowBound() per particle (room); scan; fillPeriodicRow() per particle (its row,
///      sorted by scene index, each partner once; its length); scan; the rows compacted.
///
/// Design notes
/// - Completeness. Wrapped into [−h, h), two particles i, j (x_i ≥ x_j on an axis) differ by D or
///   D − L through their nearest images, D in [0, L). When D − L is the one within reach, x_j
///   lies within reach of −h, so j has a ghost at x_j + L, within reach of x_i. Per axis the
///   particle nearer its lower end carries the shift; when the two axes shift different
///   particles, their two ghosts meet. Pairs found through several pairs of images are merged in
///   each particle's row (fillPeriodicRow).
/// - Determinism. The ghosts are numbered by a scan of per-particle counts (the particle order,
///   then x, y, corner), and each row is sorted by scene index with its duplicates dropped: the
///   rows do not depend on the threads or on how the sweep found them.
/// - Rounding. A ghost's shifted coordinate and a difference across the boundary are rounded at
///   the size of the box; the skin's rounding margin has a term for it (skinClosureLimit's W),
///   the detection grows the radii by twice that margin (periodicGrowth()), and a stand-alone
///   detection filters with the exact predicate (findPairs()).
#pragma once
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/periodic.hpp"
#include "tumble/kernels/records.hpp"

namespace tumble {

/// What a periodic detection grows the radii by, beyond half the skin: the sweep compares ghost
/// coordinates shifted by a period, rounded at the size of the box, where the exact predicate
/// takes the nearest image of a difference, rounded otherwise; twice the rounding margin of such
/// a difference covers both (a pair within rounding of touching across the boundary was missed
/// without it when the list is rebuilt every step: PeriodicTest.PairsWithinRoundingOfTouching...).
inline float periodicGrowth(float maxRadius, const PeriodicBox& box) {
  return static_cast<float>(2.0 * roundingMargin(0.0f, maxRadius, periodicRoundingReach(box)));
}

/// How near a lower end of the periodic box a particle of (grown) radius up to maxRadius gets a
/// ghost: any pair it may form, 2 maxRadius, and that margin again.
inline float ghostReach(float maxRadius, const PeriodicBox& box) {
  return 2.0f * maxRadius + periodicGrowth(maxRadius, box);
}

/// The images a periodic detection sweeps: the n particles (sweep indices 0 .. n), then the
/// ghosts: one shifted by +L on x of every particle within `reach` of −h on x, one shifted on y
/// likewise, one shifted on both (the corner) of every particle within reach of both. Any two
/// particles whose minimum image lies within reach (< L) are then within reach through some pair
/// of images, so the sweep finds every such pair, some more than once. Particle i's ghosts are
/// the sweep indices n + ghostFirst[i] .. n + ghostFirst[i + 1]; ghost g stands for ghostOf[g].
struct PeriodicImagesView {
  std::uint32_t n = 0;
  const std::uint32_t* ghostFirst = nullptr;  // n + 1
  const std::uint32_t* ghostOf = nullptr;
  /// The particle that sweep index a stands for.
  TUMBLE_HD std::uint32_t particleOf(std::uint32_t a) const { return a < n ? a : ghostOf[a - n]; }
};

namespace detail {
TUMBLE_HD_INLINE bool nearLowerEnd(const PeriodicBox& box, float reach, float c, int axis) {
  return box.on(axis) && c < -box.half[axis] + reach;
}
}  // namespace detail

/// Step 1's count: particle i of `in` wrapped into the box (a particle lies within L/2 of its
/// body's centre: one period at most) at x, y, z[i], with its radius and body at r, body[i];
/// returns its number of ghosts (0 to 3).
TUMBLE_HD_INLINE std::uint32_t wrapImage(const BroadphaseInput& in, const PeriodicBox& box, float reach,
                                         std::uint32_t i, float* x, float* y, float* z, float* r,
                                         std::uint32_t* body) {
  Vec3f p{in.x[i], in.y[i], in.z[i]};
  std::int32_t image[2] = {0, 0};
  wrapIntoBox(box, &p, image);
  x[i] = p.x;
  y[i] = p.y;
  z[i] = p.z;
  r[i] = in.r[i];
  body[i] = in.body[i];
  const bool nx = detail::nearLowerEnd(box, reach, p.x, 0), ny = detail::nearLowerEnd(box, reach, p.y, 1);
  return (nx ? 1u : 0u) + (ny ? 1u : 0u) + (nx && ny ? 1u : 0u);
}

/// Step 1's fill: particle i's ghosts (after wrapImage() of every particle and the scan of their
/// counts into ghostFirst) in the columns x, y, z, r, body at n + ghostFirst[i] .., and ghostOf.
TUMBLE_HD_INLINE void writeGhosts(const PeriodicBox& box, float reach, std::uint32_t n, std::uint32_t i,
                                  const std::uint32_t* ghostFirst, float* x, float* y, float* z, float* r,
                                  std::uint32_t* body, std::uint32_t* ghostOf) {
  std::uint32_t g = ghostFirst[i];
  if (g == ghostFirst[i + 1]) return;
  const bool nx = detail::nearLowerEnd(box, reach, x[i], 0), ny = detail::nearLowerEnd(box, reach, y[i], 1);
  const auto add = [&](float gx, float gy) {
    x[n + g] = gx;
    y[n + g] = gy;
    z[n + g] = z[i];
    r[n + g] = r[i];
    body[n + g] = body[i];
    ghostOf[g++] = i;
  };
  if (nx) add(x[i] + box.length[0], y[i]);
  if (ny) add(x[i], y[i] + box.length[1]);
  if (nx && ny) add(x[i] + box.length[0], y[i] + box.length[1]);
}

/// Step 3's count: room for particle i's row, the candidates of i and of its ghosts (a partner
/// found through several pairs of images counted each time).
TUMBLE_HD_INLINE std::uint32_t periodicRowBound(const SweepListView& s, const PeriodicImagesView& v, std::uint32_t i) {
  std::uint32_t c = candidateCount(s, i);
  for (std::uint32_t g = v.ghostFirst[i]; g < v.ghostFirst[i + 1]; ++g) c += candidateCount(s, v.n + g);
  return c;
}

/// Step 3's fill: particle i's row, the partners of i and of its ghosts as particles, in
/// ascending orig[·] (scene index), each once, at cand (room: periodicRowBound(); key is scratch
/// of the same size). Returns its length.
TUMBLE_HD_INLINE std::uint32_t fillPeriodicRow(const SweepListView& s, const PeriodicImagesView& v,
                                               const std::uint32_t* orig, std::uint32_t i, std::uint32_t* cand,
                                               std::uint32_t* key) {
  const auto map = [&](std::uint32_t a) { return v.particleOf(a); };
  std::uint32_t e = appendCandidates(s, orig, i, map, cand, key, 0);
  for (std::uint32_t g = v.ghostFirst[i]; g < v.ghostFirst[i + 1]; ++g)
    e = appendCandidates(s, orig, v.n + g, map, cand, key, e);
  detail::sortRow(key, cand, e);  // equal keys are the same partner: the order among them is moot
  std::uint32_t out = 0;
  for (std::uint32_t t = 0; t < e; ++t)
    if (t == 0 || key[t] != key[t - 1]) {
      key[out] = key[t];
      cand[out++] = cand[t];
    }
  return out;
}

}  // namespace tumble
