// SPDX-License-Identifier: MIT
/// @file wall.hpp
/// Plane walls as the kernels see them (issue 12): the ground and every `[[wall]]` plane. A
/// sphere meets a plane exactly as it meets the ground (groundForces(), hertzGroundForces()),
/// computed in the plane's own frame (t1, t2, n) and turned back. A plane whose normal is a
/// coordinate axis (the ground, a box's faces) uses a signed cyclic permutation of the
/// coordinates as that frame, which is exact: the ground as a plane gives today's bits.
#pragma once
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/kernels/contact.hpp"
#include "tumble/math.hpp"

namespace tumble {

/// One plane, x·n = h: the spheres are on the side n points to, in contact when groundDepth()
/// of their position in the plane's frame (toWall(), whose z is x·n) is positive, with
/// coeffs.height = h. The frame's origin is the coordinate origin, so that x·n has the
/// rounding of |x| (of the local frame, near the bodies), not of the distance to a given point.
struct PlaneWall {
  Vec3f t1, t2, n;     ///< right-handed orthonormal frame, n the normal
  std::int32_t axis;   ///< n = sign · e_axis (0, 1, 2): the exact frame; −1: a general plane
  float sign;          ///< ±1 (aligned planes)
  GroundCoeffs coeffs; ///< the ground's coefficients; height h = p·n of a point p of the plane
};

/// A vector in the plane's frame: (v·t1, v·t2, v·n). kAxis: the plane's axis (0, 1, 2: aligned,
/// n = sign e_a, t1 = e_b, t2 = sign e_c with b = a + 1, c = a + 2 mod 3: a permutation, exact),
/// or −1 for a general plane; kGroundFrame (the ground: axis 2, sign +1) is the identity. A
/// template, so that the permutation costs nothing.
inline constexpr int kGroundFrame = 3;
template <int kAxis>
TUMBLE_HD_INLINE Vec3f toWall(const PlaneWall& w, Vec3f v) {
  if constexpr (kAxis == kGroundFrame) return v;
  else if constexpr (kAxis == 0) return Vec3f{v.y, w.sign * v.z, w.sign * v.x};
  else if constexpr (kAxis == 1) return Vec3f{v.z, w.sign * v.x, w.sign * v.y};
  else if constexpr (kAxis == 2) return Vec3f{v.x, w.sign * v.y, w.sign * v.z};
  else return Vec3f{dot(v, w.t1), dot(v, w.t2), dot(v, w.n)};
}

/// The inverse of toWall(): l.x t1 + l.y t2 + l.z n.
template <int kAxis>
TUMBLE_HD_INLINE Vec3f fromWall(const PlaneWall& w, Vec3f l) {
  if constexpr (kAxis == kGroundFrame) return l;
  else if constexpr (kAxis == 0) return Vec3f{w.sign * l.z, l.x, w.sign * l.y};
  else if constexpr (kAxis == 1) return Vec3f{w.sign * l.y, w.sign * l.z, l.x};
  else if constexpr (kAxis == 2) return Vec3f{l.x, w.sign * l.y, w.sign * l.z};
  else return (l.x * w.t1 + l.y * w.t2) + l.z * w.n;
}

/// toWall(w, x).z alone, for any plane, without a branch: what the contact test reads.
/// x·n; for an aligned plane n = sign e_a, so the products with the zero components add ±0
/// and it equals sign · x_a, the value groundDepth() sees there.
TUMBLE_HD_INLINE float wallHeight(const PlaneWall& w, Vec3f x) { return dot(x, w.n); }

/// A contact side (lever, V, Ω) in the plane's frame (a rotation: Ω turns as a vector).
template <int kAxis>
TUMBLE_HD_INLINE ContactSide toWall(const PlaneWall& w, const ContactSide& s) {
  return ContactSide{toWall<kAxis>(w, s.offset), toWall<kAxis>(w, s.v), toWall<kAxis>(w, s.omega)};
}

}  // namespace tumble
