// SPDX-License-Identifier: MIT
/// @file wall.hpp
/// Walls as the kernels see them (issue 12): the ground, every `[[wall]]` plane and every
/// revolved wall (a cylinder, a cone, a disk or a ring). A sphere meets a wall exactly as it
/// meets the ground (groundForces(), hertzGroundForces()), computed in a frame (t1, t2, n) of
/// the wall's surface and turned back. A plane whose normal is a coordinate axis (the ground, a
/// box's faces) uses a signed cyclic permutation of the coordinates as that frame, which is
/// exact: the ground as a plane gives today's bits. A revolved wall's frame is that of its
/// surface at the point nearest the sphere (revolvedContact()).
#pragma once
#include <cfloat>
#include <cmath>
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/kernels/contact.hpp"
#include "tumble/math.hpp"

namespace tumble {

/// Wall::axis of a general plane and of a revolved wall (0, 1, 2: a plane n = sign e_axis).
inline constexpr std::int32_t kGeneralPlane = -1;
inline constexpr std::int32_t kRevolvedWall = -2;
/// Wall::axis of a mesh wall: only its coeffs are read here; its triangles are in the
/// MeshView (kernels/mesh.hpp), and the plane loops skip it.
inline constexpr std::int32_t kMeshWall = -3;

/// One wall.
///
/// A plane, x·n = h: the spheres are on the side n points to, in contact when groundDepth()
/// of their position in the plane's frame (toWall(), whose z is x·n) is positive, with
/// coeffs.height = h. The frame's origin is the coordinate origin, so that x·n has the
/// rounding of |x| (of the local frame, near the bodies), not of the distance to a given point.
///
/// A revolved wall (axis == kRevolvedWall): n is the axis's direction and `centre` its point
/// nearest the origin (near the bodies, so that s below has the rounding of the bodies'
/// coordinates, not of the wall's extent); the surface is the segment from (start, radius0) to
/// (start + length, radius1) in (s, ρ) coordinates (s = (x − centre)·n, ρ the distance from the
/// axis), turned about the axis; t1, t2 ⟂ n (t1 × t2 = n) stand for the radial direction of a
/// point on the axis. coeffs.height is 0.
struct Wall {
  Vec3f t1, t2, n;     ///< right-handed orthonormal frame, n the normal (a plane) or the axis
  std::int32_t axis;   ///< n = sign · e_axis (0, 1, 2): the exact frame; kGeneralPlane; kRevolvedWall
  float sign;          ///< ±1 (aligned planes)
  GroundCoeffs coeffs; ///< the ground's coefficients; a plane's height h = p·n of a point p of it
  Vec3f centre;        ///< revolved: the point of the axis nearest the frame's origin
  float start;         ///< revolved: where the segment starts along the axis from centre
  float length, radius0, radius1;  ///< revolved: the segment (WallDef)
  /// The surface moves this step (setWallMotion()): the velocity of its material at a point p
  /// is velocity + omega n × (p − centre).
  std::uint32_t moving;
  Vec3f velocity;
  float omega;
  /// Where the wall was given (at τ = 0; setWallMotion() shifts coeffs.height, or centre and
  /// start, from these): a plane's h, a revolved wall's centre and start.
  float restHeight;
  Vec3f restCentre;
  float restStart;
};

/// A vector in the plane's frame: (v·t1, v·t2, v·n). kAxis: the plane's axis (0, 1, 2: aligned,
/// n = sign e_a, t1 = e_b, t2 = sign e_c with b = a + 1, c = a + 2 mod 3: a permutation, exact),
/// or −1 for a general plane; kGroundFrame (the ground: axis 2, sign +1) is the identity. A
/// template, so that the permutation costs nothing.
inline constexpr int kGroundFrame = 3;
template <int kAxis>
TUMBLE_HD_INLINE Vec3f toWall(const Wall& w, Vec3f v) {
  if constexpr (kAxis == kGroundFrame) return v;
  else if constexpr (kAxis == 0) return Vec3f{v.y, w.sign * v.z, w.sign * v.x};
  else if constexpr (kAxis == 1) return Vec3f{v.z, w.sign * v.x, w.sign * v.y};
  else if constexpr (kAxis == 2) return Vec3f{v.x, w.sign * v.y, w.sign * v.z};
  else return Vec3f{dot(v, w.t1), dot(v, w.t2), dot(v, w.n)};
}

/// The inverse of toWall(): l.x t1 + l.y t2 + l.z n.
template <int kAxis>
TUMBLE_HD_INLINE Vec3f fromWall(const Wall& w, Vec3f l) {
  if constexpr (kAxis == kGroundFrame) return l;
  else if constexpr (kAxis == 0) return Vec3f{w.sign * l.z, l.x, w.sign * l.y};
  else if constexpr (kAxis == 1) return Vec3f{w.sign * l.y, w.sign * l.z, l.x};
  else if constexpr (kAxis == 2) return Vec3f{l.x, w.sign * l.y, w.sign * l.z};
  else return (l.x * w.t1 + l.y * w.t2) + l.z * w.n;
}

/// toWall(w, x).z alone, for any plane, without a branch: what the contact test reads.
/// x·n; for an aligned plane n = sign e_a, so the products with the zero components add ±0
/// and it equals sign · x_a, the value groundDepth() sees there.
TUMBLE_HD_INLINE float wallHeight(const Wall& w, Vec3f x) { return dot(x, w.n); }

/// A contact side (lever, V, Ω) in the plane's frame (a rotation: Ω turns as a vector).
template <int kAxis>
TUMBLE_HD_INLINE ContactSide toWall(const Wall& w, const ContactSide& s) {
  return ContactSide{toWall<kAxis>(w, s.offset), toWall<kAxis>(w, s.v), toWall<kAxis>(w, s.omega)};
}

/// The velocity of a moving wall's material at p (Wall::moving): a revolved wall turns about
/// its axis (through centre), a plane moves along itself (omega 0).
TUMBLE_HD_INLINE Vec3f wallVelocity(const Wall& w, Vec3f p) {
  return w.velocity + w.omega * cross(w.n, p - w.centre);
}

/// Where a sphere centre x stands against a revolved wall: its distance from the surface and
/// the surface's frame at the nearest point (n from the surface towards x), as a Wall whose
/// plane through that point is the contact's (coeffs as w's, height 0: the sphere is at height
/// `dist` in it).
///
/// In the meridian half-plane of x the surface is the segment from (s0, radius0) to (s0 +
/// length, radius1): the nearest point of the surface is the nearest point of the segment to
/// (s, ρ), its end points included (the rims), so a sphere on a rim meets one point, once. Off
/// the rims the distance is the perpendicular one, ((ρ − r0) Δs − (s − s0) Δρ) / L, which for a
/// cylinder does not read s at all (no rounding of the distance along a long pipe). On the
/// axis (ρ = 0) the half-plane is that of t1. With x on the surface (dist = 0) n is the
/// segment's normal (−Δρ, Δs)/L.
///
/// The frame: on a disk or ring's face the wall's own (t1, ±t2, ±axis), fixed as a plane's, so
/// that the stick spring does not turn as a sphere goes round the axis; elsewhere t2 is the
/// azimuthal direction a × e_ρ and t1 = t2 × n (the spring turns with the curved surface).
struct RevolvedPoint {
  float dist;
  Wall frame;
};
TUMBLE_HD_INLINE RevolvedPoint revolvedContact(const Wall& w, Vec3f x) {
  const Vec3f d = x - w.centre;
  const float s = dot(d, w.n);
  Vec3f q = d - s * w.n;
  q = q - dot(q, w.n) * w.n;  // twice: near the axis, one projection leaves q's rounding along n
  const float rho = std::sqrt(dot(q, q));
  const Vec3f er = rho > 0.0f ? (1.0f / rho) * q : w.t1;
  const float es = w.length, eq = w.radius1 - w.radius0;
  const float ls = s - w.start, lr = rho - w.radius0;  // from the segment's first end
  const float len2 = es * es + eq * eq, inv = 1.0f / std::sqrt(len2);
  const float t0 = (ls * es + lr * eq) / len2;
  float dist, ns, nr;
  bool face = false;
  if (t0 > 0.0f && t0 < 1.0f) {  // the perpendicular foot lies on the segment
    const float h = (lr * es - ls * eq) * inv;  // signed, positive on the side of (−Δρ, Δs)
    const float sign = h < 0.0f ? -1.0f : 1.0f;
    dist = sign * h;
    ns = -sign * eq * inv;
    nr = sign * es * inv;
    face = es == 0.0f;
  } else {  // a rim
    const float ds = t0 <= 0.0f ? ls : ls - es, dr = t0 <= 0.0f ? lr : lr - eq;
    dist = std::sqrt(ds * ds + dr * dr);
    if (dist > 0.0f) {
      ns = ds / dist;
      nr = dr / dist;
    } else {
      ns = -eq * inv;
      nr = es * inv;
    }
  }
  RevolvedPoint out{dist, w};
  if (face) {  // a disk's face: n = ns axis, ns = ±1 (t1 as the wall's)
    out.frame.n = ns * w.n;
    out.frame.t2 = ns * w.t2;
  } else {
    out.frame.n = ns * w.n + nr * er;
    out.frame.t2 = cross(w.n, er);
    out.frame.t1 = cross(out.frame.t2, out.frame.n);
  }
  out.frame.axis = kGeneralPlane;
  out.frame.sign = 1.0f;
  out.frame.coeffs.height = 0.0f;
  return out;
}

/// The distance of a sphere centre from any wall along its normal: x·n − h for a plane (negative
/// behind it), revolvedContact()'s for a revolved wall; FLT_MAX for a mesh wall, whose triangles
/// are measured by the mesh's own functions (mesh.hpp). In contact when it is below the radius.
TUMBLE_HD_INLINE float wallGap(const Wall& w, Vec3f x) {
  if (w.axis == kMeshWall) return FLT_MAX;  // a mesh's triangles are met through kernels/mesh.hpp
  return w.axis == kRevolvedWall ? revolvedContact(w, x).dist : wallHeight(w, x) - w.coeffs.height;
}

}  // namespace tumble
