// SPDX-License-Identifier: MIT
/// @file integrate.hpp
/// Particle state from body state (SPEC §2.1) and body integration (SPEC §2.7).
#pragma once
#include <cmath>

#include "tumble/hd.hpp"
#include "tumble/math.hpp"

namespace tumble {

/// World angular velocity Ω = R I0⁻¹ Rᵀ L (the report writes A; it is Ω), R = rotationMatrix(Q).
TUMBLE_HD_INLINE Vec3f angularVelocity(const Mat3f& R, const Sym3f& invInertia, Vec3f L) {
  return mul(R, mul(invInertia, mulTransposed(R, L)));
}
TUMBLE_HD_INLINE Vec3f angularVelocity(Quatf q, const Sym3f& invInertia, Vec3f L) {
  return angularVelocity(rotationMatrix(q), invInertia, L);
}

/// Position of a particle with body-frame offset u on a body at X with rotation matrix R
/// (rotationMatrix(Q)): x = X + R u. Every pipeline, the oracle and the guards compute particle
/// positions with this one expression, so they agree to the bit.
TUMBLE_HD_INLINE Vec3f particlePosition(Vec3f X, const Mat3f& R, Vec3f u) { return X + mul(R, u); }

/// Velocity of the body's material at `arm` from its centre: V + Ω × arm.
TUMBLE_HD_INLINE Vec3f pointVelocity(Vec3f V, Vec3f omega, Vec3f arm) { return V + cross(omega, arm); }

/// Translation, leapfrog ("kick-drift") form of Störmer–Verlet: V ← V + (F/M) dt, X ← X + V dt.
/// Velocities used by the forces are those at the start of the step.
TUMBLE_HD_INLINE void integrateTranslation(Vec3f F, float invMass, float dt, Vec3f* ioX, Vec3f* ioV) {
  const float s = invMass * dt;
  *ioV = *ioV + s * F;
  *ioX = *ioX + dt * *ioV;
}

/// Rotation as in the report: L ← L + T dt (forward Euler), then the exponential map
/// Q ← [cos(|Ω|dt/2), Ω/|Ω| sin(|Ω|dt/2)] ⊗ Q with Ω from the new L, renormalised.
/// Returns Ω of the new state (for the next step's contact-point velocities); *outR receives
/// rotationMatrix() of the new Q (for the particle positions).
TUMBLE_HD_INLINE Vec3f integrateRotation(Vec3f T, const Sym3f& invInertia, float dt, Vec3f* ioL, Quatf* ioQ,
                                         Mat3f* outR) {
  *ioL = *ioL + dt * T;
  const Vec3f omega = angularVelocity(*ioQ, invInertia, *ioL);
  const float w = std::sqrt(dot(omega, omega));
  if (w > 0.0f) {
    float s, c;
    sinCos(0.5f * w * dt, &s, &c);
    const float k = s / w;
    const Quatf dq{c, omega.x * k, omega.y * k, omega.z * k};
    *ioQ = normalized(mul(dq, *ioQ));
  }
  *outR = rotationMatrix(*ioQ);
  return angularVelocity(*outR, invInertia, *ioL);
}

namespace detail {

/// One exact sub-flow of the free rotation about principal axis A (0, 1, 2) by angle θ:
/// the body frame turns by +θ about its axis A (Q ← Q ⊗ [cos θ/2, sin θ/2 e_A]) and the
/// body-frame angular momentum π turns by −θ about the same axis, so that L = R π is unchanged.
template <int A>
TUMBLE_HD_INLINE void freeRotationAbout(float theta, Vec3f* pi, Quatf* q) {
  float s, c;
  sinCos(theta, &s, &c);
  float hs, hc;
  sinCos(0.5f * theta, &hs, &hc);
  Vec3f p = *pi;
  Quatf r{hc, 0.0f, 0.0f, 0.0f};
  if (A == 0) {
    p = Vec3f{p.x, c * p.y + s * p.z, c * p.z - s * p.y};
    r.x = hs;
  } else if (A == 1) {
    p = Vec3f{c * p.x - s * p.z, p.y, c * p.z + s * p.x};
    r.y = hs;
  } else {
    p = Vec3f{c * p.x + s * p.y, c * p.y - s * p.x, p.z};
    r.z = hs;
  }
  *pi = p;
  *q = mul(*q, r);
}

}  // namespace detail

/// Rotation by symplectic splitting (Dullweber, Leimkuhler & McLachlan, J. Chem. Phys. 107,
/// 5840, 1997): L += T dt (the kick, as in the report's scheme), then the free rotation over dt
/// split as H = H1 + H2 + H3, H_a = π_a² / (2 I_a), composed as
/// ½h·1, ½h·2, h·3, ½h·2, ½h·1 — each an exact rotation about a principal axis. Requires the body
/// frame to be the principal frame (invInertia diagonal; World::fromScene arranges that when this
/// scheme is chosen). L is not touched by the drift, so |L| is conserved exactly in free flight;
/// the method is symplectic and time-reversible, so the kinetic energy stays bounded (no drift).
TUMBLE_HD_INLINE Vec3f integrateRotationSplitting(Vec3f T, const Sym3f& invInertia, float dt, Vec3f* ioL,
                                                  Quatf* ioQ, Mat3f* outR) {
  *ioL = *ioL + dt * T;
  Vec3f pi = rotateInv(*ioQ, *ioL);
  Quatf q = *ioQ;
  const float h = 0.5f * dt;
  detail::freeRotationAbout<0>(h * pi.x * invInertia.xx, &pi, &q);
  detail::freeRotationAbout<1>(h * pi.y * invInertia.yy, &pi, &q);
  detail::freeRotationAbout<2>(dt * pi.z * invInertia.zz, &pi, &q);
  detail::freeRotationAbout<1>(h * pi.y * invInertia.yy, &pi, &q);
  detail::freeRotationAbout<0>(h * pi.x * invInertia.xx, &pi, &q);
  *ioQ = normalized(q);
  *outR = rotationMatrix(*ioQ);
  return angularVelocity(*outR, invInertia, *ioL);
}

}  // namespace tumble
