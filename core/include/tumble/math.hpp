// SPDX-License-Identifier: MIT
/// @file math.hpp
/// Small vector, quaternion and symmetric-matrix PODs shared by host and device code.
///
/// Determinism: every function here is a fixed sequence of IEEE + - * / and sqrt, so with
/// FMA contraction off (-ffp-contract=off on the host, --fmad=false under nvcc) it gives the
/// same bits on CPU and GPU. No library transcendentals: sinCos() is our own polynomial.
#pragma once
#include <cmath>

#include "tumble/hd.hpp"

namespace tumble {

/// 3-vector of floats (trivially copyable).
struct Vec3f {
  float x, y, z;
};

/// Unit quaternion w + xi + yj + zk (trivially copyable). Rotates body-frame vectors to world.
struct Quatf {
  float w, x, y, z;
};

/// Symmetric 3x3 matrix stored as xx, yy, zz, xy, xz, yz.
struct Sym3f {
  float xx, yy, zz, xy, xz, yz;
};

/// 3x3 matrix by rows (trivially copyable).
struct Mat3f {
  float xx, xy, xz, yx, yy, yz, zx, zy, zz;
};

TUMBLE_HD_INLINE Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
TUMBLE_HD_INLINE Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
TUMBLE_HD_INLINE Vec3f operator-(Vec3f a) { return {-a.x, -a.y, -a.z}; }
TUMBLE_HD_INLINE Vec3f operator*(float s, Vec3f a) { return {s * a.x, s * a.y, s * a.z}; }
TUMBLE_HD_INLINE Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
TUMBLE_HD_INLINE Vec3f& operator+=(Vec3f& a, Vec3f b) {
  a.x += b.x;
  a.y += b.y;
  a.z += b.z;
  return a;
}
TUMBLE_HD_INLINE Vec3f& operator-=(Vec3f& a, Vec3f b) {
  a.x -= b.x;
  a.y -= b.y;
  a.z -= b.z;
  return a;
}
TUMBLE_HD_INLINE float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
TUMBLE_HD_INLINE Vec3f cross(Vec3f a, Vec3f b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
TUMBLE_HD_INLINE float norm2(Vec3f a) { return dot(a, a); }
TUMBLE_HD_INLINE float norm(Vec3f a) { return std::sqrt(dot(a, a)); }

/// Hamilton product a ⊗ b (apply b first, then a).
TUMBLE_HD_INLINE Quatf mul(Quatf a, Quatf b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
          a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
          a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

/// q normalised to unit length; the identity if q is zero.
TUMBLE_HD_INLINE Quatf normalized(Quatf q) {
  const float n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  if (!(n2 > 0.0f)) return {1.0f, 0.0f, 0.0f, 0.0f};
  const float inv = 1.0f / std::sqrt(n2);
  return {q.w * inv, q.x * inv, q.y * inv, q.z * inv};
}

/// R(q) v for a unit quaternion q (v' = v + 2w (u×v) + 2 u×(u×v), u = vector part).
TUMBLE_HD_INLINE Vec3f rotate(Quatf q, Vec3f v) {
  const Vec3f u{q.x, q.y, q.z};
  const Vec3f t = 2.0f * cross(u, v);
  return v + q.w * t + cross(u, t);
}

/// R(q)ᵀ v = R(q⁻¹) v for a unit quaternion q.
TUMBLE_HD_INLINE Vec3f rotateInv(Quatf q, Vec3f v) { return rotate(Quatf{q.w, -q.x, -q.y, -q.z}, v); }

/// The rotation matrix R(q) of a unit quaternion (the standard formula, one fixed sequence of
/// operations): R v = rotate(q, v) to rounding, and cheaper when one q rotates many vectors.
TUMBLE_HD_INLINE Mat3f rotationMatrix(Quatf q) {
  const float x2 = q.x + q.x, y2 = q.y + q.y, z2 = q.z + q.z;
  const float xx = q.x * x2, yy = q.y * y2, zz = q.z * z2;
  const float xy = q.x * y2, xz = q.x * z2, yz = q.y * z2;
  const float wx = q.w * x2, wy = q.w * y2, wz = q.w * z2;
  return {1.0f - (yy + zz), xy - wz, xz + wy,
          xy + wz, 1.0f - (xx + zz), yz - wx,
          xz - wy, yz + wx, 1.0f - (xx + yy)};
}

/// M v.
TUMBLE_HD_INLINE Vec3f mul(const Mat3f& m, Vec3f v) {
  return {m.xx * v.x + m.xy * v.y + m.xz * v.z, m.yx * v.x + m.yy * v.y + m.yz * v.z,
          m.zx * v.x + m.zy * v.y + m.zz * v.z};
}

/// Mᵀ v.
TUMBLE_HD_INLINE Vec3f mulTransposed(const Mat3f& m, Vec3f v) {
  return {m.xx * v.x + m.yx * v.y + m.zx * v.z, m.xy * v.x + m.yy * v.y + m.zy * v.z,
          m.xz * v.x + m.yz * v.y + m.zz * v.z};
}

/// S v for a symmetric matrix S.
TUMBLE_HD_INLINE Vec3f mul(const Sym3f& s, Vec3f v) {
  return {s.xx * v.x + s.xy * v.y + s.xz * v.z, s.xy * v.x + s.yy * v.y + s.yz * v.z,
          s.xz * v.x + s.yz * v.y + s.zz * v.z};
}

/// Two unit vectors t, u completing the unit vector n to a right-handed orthonormal frame
/// (t, u, n): t = n × e / |n × e| with e the coordinate axis least aligned with n (the first of
/// equals), u = n × t. In double on the host (the sweep frame's p, q of its axis, a general
/// wall's t1, t2), in float in the kernels (a mesh contact's tangent plane).
template <class T>
TUMBLE_HD_INLINE void perpendicularPair(const T n[3], T t[3], T u[3]) {
  int least = 0;
  for (int k = 1; k < 3; ++k)
    if ((n[k] < T(0) ? -n[k] : n[k]) < (n[least] < T(0) ? -n[least] : n[least])) least = k;
  T e[3] = {T(0), T(0), T(0)};
  e[least] = T(1);
  t[0] = n[1] * e[2] - n[2] * e[1];
  t[1] = n[2] * e[0] - n[0] * e[2];
  t[2] = n[0] * e[1] - n[1] * e[0];
  const T tn = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
  for (int k = 0; k < 3; ++k) t[k] /= tn;
  u[0] = n[1] * t[2] - n[2] * t[1];
  u[1] = n[2] * t[0] - n[0] * t[2];
  u[2] = n[0] * t[1] - n[1] * t[0];
}

/// sin and cos of a float angle from our own polynomials, so that host and device give the same
/// bits. Range reduction by a two-constant Cody–Waite split of π/2 (exact for |a| up to ~1e5),
/// then Taylor polynomials on [-π/4, π/4] (error < 1 ulp·few). Beyond 1e5 (a rotation by ω dt
/// that large means the run has already diverged) the angle is first reduced modulo the float
/// nearest 2π (fmodf is exact, so still the same bits everywhere): the result stays a bounded
/// sine and cosine, and the integer conversion below stays within range. NaN for ±∞ and NaN.
TUMBLE_HD_INLINE void sinCos(float a, float* outSin, float* outCos) {
  if (!(fabsf(a) <= 1e5f)) {
    if (!(fabsf(a) <= 3.40282347e38f)) {
      *outSin = *outCos = a - a;  // NaN
      return;
    }
    a = fmodf(a, 6.28318548f);
  }
  // k = round(a · 2/π); r = a − k·π/2 computed with a split constant.
  const float kTwoOverPi = 0.636619772367581343f;
  const float kPiOver2Hi = 1.5703125f;               // 8 significant bits: k·hi is exact
  const float kPiOver2Lo = 4.83826794897e-4f;        // π/2 − hi
  float kf = a * kTwoOverPi;
  kf = kf >= 0.0f ? static_cast<float>(static_cast<long long>(kf + 0.5f))
                  : -static_cast<float>(static_cast<long long>(-kf + 0.5f));
  const float r = (a - kf * kPiOver2Hi) - kf * kPiOver2Lo;
  const float r2 = r * r;
  // Taylor to r^9 / r^8: remainder below 2e-9 on |r| ≤ π/4.
  const float s = r * (1.0f + r2 * (-1.0f / 6.0f + r2 * (1.0f / 120.0f + r2 * (-1.0f / 5040.0f +
                                                                              r2 * (1.0f / 362880.0f)))));
  const float c = 1.0f + r2 * (-0.5f + r2 * (1.0f / 24.0f + r2 * (-1.0f / 720.0f +
                                                                  r2 * (1.0f / 40320.0f))));
  const long long k = static_cast<long long>(kf);
  switch (static_cast<int>(k & 3)) {
    case 0: *outSin = s; *outCos = c; break;
    case 1: *outSin = c; *outCos = -s; break;
    case 2: *outSin = -s; *outCos = -c; break;
    default: *outSin = -c; *outCos = s; break;
  }
}

}  // namespace tumble
