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

/// One plane: the spheres are on the side n points to, in contact when groundDepth() of their
/// position in the plane's frame (wallPosition()) is positive.
struct PlaneWall {
  Vec3f origin;        ///< a point of the plane (a general plane's frame origin)
  Vec3f t1, t2, n;     ///< right-handed orthonormal frame, n the normal
  std::int32_t axis;   ///< n = sign · e_axis (0, 1, 2): the exact frame; −1: a general plane
  float sign;          ///< ±1 (aligned planes)
  GroundCoeffs coeffs; ///< the ground's coefficients; height: sign · origin[axis] (aligned), 0 (general)
};

namespace detail {
TUMBLE_HD_INLINE float component(Vec3f v, std::int32_t k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }
}  // namespace detail

/// A vector in the plane's frame: (v·t1, v·t2, v·n). Aligned on axis a (b = a + 1, c = a + 2,
/// mod 3): (v_b, sign v_c, sign v_a), exact.
TUMBLE_HD_INLINE Vec3f toWall(const PlaneWall& w, Vec3f v) {
  if (w.axis >= 0) {
    const std::int32_t a = w.axis, b = a == 2 ? 0 : a + 1, c = b == 2 ? 0 : b + 1;
    return Vec3f{detail::component(v, b), w.sign * detail::component(v, c), w.sign * detail::component(v, a)};
  }
  return Vec3f{dot(v, w.t1), dot(v, w.t2), dot(v, w.n)};
}

/// The inverse of toWall(): l.x t1 + l.y t2 + l.z n.
TUMBLE_HD_INLINE Vec3f fromWall(const PlaneWall& w, Vec3f l) {
  if (w.axis >= 0) {
    const std::int32_t a = w.axis, b = a == 2 ? 0 : a + 1;
    float out[3];
    out[b] = l.x;
    out[b == 2 ? 0 : b + 1] = w.sign * l.y;
    out[a] = w.sign * l.z;
    return Vec3f{out[0], out[1], out[2]};
  }
  return (l.x * w.t1 + l.y * w.t2) + l.z * w.n;
}

/// A point in the plane's frame, whose z is measured against coeffs.height by groundDepth():
/// aligned planes permute x itself (height = sign · origin[axis]), general ones take x − origin.
TUMBLE_HD_INLINE Vec3f wallPosition(const PlaneWall& w, Vec3f x) { return toWall(w, w.axis >= 0 ? x : x - w.origin); }

/// A contact side (lever, V, Ω) in the plane's frame (a rotation: Ω turns as a vector).
TUMBLE_HD_INLINE ContactSide toWall(const PlaneWall& w, const ContactSide& s) {
  return ContactSide{toWall(w, s.offset), toWall(w, s.v), toWall(w, s.omega)};
}

}  // namespace tumble
