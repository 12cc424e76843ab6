// SPDX-License-Identifier: MIT
/// @file overlap.hpp
/// The exact sphere overlap predicate, shared by every pipeline and the brute-force oracle so
/// that contacts exactly at the boundary are decided identically everywhere.
#pragma once
#include "tumble/hd.hpp"

namespace tumble {

/// |x_i − x_j|² < (r_i + r_j)², evaluated in float in a fixed order. Touching spheres
/// (equality) do not overlap.
TUMBLE_HD_INLINE bool spheresOverlap(float xi, float yi, float zi, float ri, float xj, float yj, float zj,
                                     float rj) {
  const float dx = xi - xj;
  const float dy = yi - yj;
  const float dz = zi - zj;
  const float s = ri + rj;
  return dx * dx + dy * dy + dz * dz < s * s;
}

/// The same predicate, also handing out what it computed: d = x_i − x_j and |d|² (the force
/// stage reuses them). Decides exactly as spheresOverlap().
TUMBLE_HD_INLINE bool spheresOverlap(float xi, float yi, float zi, float ri, float xj, float yj, float zj, float rj,
                                     float* outDx, float* outDy, float* outDz, float* outD2) {
  const float dx = xi - xj;
  const float dy = yi - yj;
  const float dz = zi - zj;
  const float s = ri + rj;
  const float d2 = dx * dx + dy * dy + dz * dz;
  *outDx = dx;
  *outDy = dy;
  *outDz = dz;
  *outD2 = d2;
  return d2 < s * s;
}

}  // namespace tumble
