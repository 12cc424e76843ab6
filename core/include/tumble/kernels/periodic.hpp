// SPDX-License-Identifier: MIT
/// @file periodic.hpp
/// Periodic boundaries on x and/or y as the kernels see them (`[periodic]`, docs/model.md#periodic-boundaries),
/// written once for every stage that compares two positions: the force stage, the exact
/// predicate of the contact list and of pairs(), the skin test, the guard's contact sums and the
/// brute-force oracle.
///
/// In the frame a run integrates in, a periodic axis has its origin at the box's centre
/// (LocalFrame::of), so the box is [−h, h) with period L = 2h. A body's centre of mass X is kept
/// in it: a body that leaves through h is moved by −L and one that leaves through −h by +L, and
/// its image counter (BodyRow::image, BodyState::imageX/imageY) counts the crossings, so that
/// X + n L is where it would be without the boundary. For |x| in [h, 3h] these moves are exact
/// (Sterbenz's lemma: x − 2h with h ≤ x ≤ 4h), so wrapping changes no bit of the motion.
///
/// Two positions are compared through the minimum image: on a periodic axis their difference d
/// becomes d − L above h and d + L below −h. Seen from the other side every operand is negated,
/// and so is the result, exactly: both sides of a contact stay exact negations, as without
/// boundaries (kernels/contact.hpp). One period suffices for every pair that can touch or be a
/// candidate: a scene's period exceeds 2 (largest body extent + largest radius + skin)
/// (PeriodReach, periodTooShort()), so such a pair's plain difference lies within 1.5 L.
#pragma once
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/math.hpp"

namespace tumble {

/// The periodic axes of a run in its integration frame (kernelPeriodic()); axes = 0: none.
struct PeriodicBox {
  std::uint32_t axes = 0;             ///< bit 0: x is periodic, bit 1: y
  float half[2] = {0.0f, 0.0f};       ///< h: the box is [−h, h) on the axis
  float length[2] = {0.0f, 0.0f};     ///< the period L = 2h
  TUMBLE_HD bool on(int axis) const { return ((axes >> axis) & 1u) != 0u; }
};

/// The minimum image of a difference d on an axis of period `length` (half = length / 2):
/// d − L above half, d + L below −half, d otherwise. minimumImage(−d) = −minimumImage(d) exactly.
/// In float for the kernels, in double for the guard's sums.
template <class T>
TUMBLE_HD_INLINE T minimumImage(T d, T half, T length) {
  return d > half ? d - length : (d < -half ? d + length : d);
}

/// The difference a − b of two positions, the minimum image on the periodic axes.
TUMBLE_HD_INLINE Vec3f periodicDifference(const PeriodicBox& b, Vec3f a, Vec3f c) {
  Vec3f d{a.x - c.x, a.y - c.y, a.z - c.z};
  if (b.axes & 1u) d.x = minimumImage<float>(d.x, b.half[0], b.length[0]);
  if (b.axes & 2u) d.y = minimumImage<float>(d.y, b.half[1], b.length[1]);
  return d;
}

/// spheresOverlap() (kernels/overlap.hpp) between nearest images: |d|² < (r_i + r_j)² with
/// d = periodicDifference(x_i, x_j), in float in a fixed order; d and |d|² handed out for the
/// force stage. With no periodic axis it decides, and computes, exactly as spheresOverlap().
TUMBLE_HD_INLINE bool spheresOverlap(const PeriodicBox& b, float xi, float yi, float zi, float ri, float xj, float yj,
                                     float zj, float rj, float* outDx, float* outDy, float* outDz, float* outD2) {
  const Vec3f d = periodicDifference(b, Vec3f{xi, yi, zi}, Vec3f{xj, yj, zj});
  const float s = ri + rj;
  const float d2 = d.x * d.x + d.y * d.y + d.z * d.z;
  *outDx = d.x;
  *outDy = d.y;
  *outDz = d.z;
  *outD2 = d2;
  return d2 < s * s;
}

TUMBLE_HD_INLINE bool spheresOverlap(const PeriodicBox& b, float xi, float yi, float zi, float ri, float xj, float yj,
                                     float zj, float rj) {
  float dx, dy, dz, d2;
  return spheresOverlap(b, xi, yi, zi, ri, xj, yj, zj, rj, &dx, &dy, &dz, &d2);
}

/// The size at which a difference across a periodic boundary is rounded, W of the skin's
/// rounding margin (skinClosureLimit()): the particles compared lie within 1.5 L of the box's
/// centre (a body's spheres reach less than L/2 beyond the box) and the detection's ghost images
/// one L further; 2 L bounds them. 0 without periodic axes.
inline double periodicRoundingReach(const PeriodicBox& b) {
  double w = 0.0;
  for (int a = 0; a < 2; ++a)
    if (b.on(a) && 2.0 * double(b.length[a]) > w) w = 2.0 * double(b.length[a]);
  return w;
}

/// Moves a body's centre that left the box back by one period on each periodic axis and counts
/// the crossing in image[axis] (+1 through h, −1 through −h). Exact for |x| ≤ 3h (see the file
/// comment); a body moving more than a period in one step is not caught up at once.
TUMBLE_HD_INLINE void wrapIntoBox(const PeriodicBox& b, Vec3f* x, std::int32_t* image) {
  float* c[2] = {&x->x, &x->y};
  for (int a = 0; a < 2; ++a) {
    if (!b.on(a)) continue;
    if (*c[a] >= b.half[a]) {
      *c[a] = *c[a] - b.length[a];
      ++image[a];
    } else if (*c[a] < -b.half[a]) {
      *c[a] = *c[a] + b.length[a];
      --image[a];
    }
  }
}

}  // namespace tumble
