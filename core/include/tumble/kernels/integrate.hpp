// SPDX-License-Identifier: MIT
/// @file integrate.hpp
/// Particle state from body state (SPEC §2.1) and body integration (SPEC §2.7).
#pragma once
#include <cmath>

#include "tumble/hd.hpp"
#include "tumble/math.hpp"

namespace tumble {

/// World angular velocity Ω = R I0⁻¹ Rᵀ L (the report writes A; it is Ω).
TUMBLE_HD_INLINE Vec3f angularVelocity(Quatf q, const Sym3f& invInertia, Vec3f L) {
  return rotate(q, mul(invInertia, rotateInv(q, L)));
}

/// Particle position and velocity from its body: x = X + R u, v = V + Ω × R u. Returns R u.
TUMBLE_HD_INLINE Vec3f particleFromBody(Vec3f X, Vec3f V, Quatf q, Vec3f omega, Vec3f u, Vec3f* outX,
                                        Vec3f* outV) {
  const Vec3f ru = rotate(q, u);
  *outX = X + ru;
  *outV = V + cross(omega, ru);
  return ru;
}

/// Translation, leapfrog ("kick-drift") form of Störmer–Verlet: V ← V + (F/M) dt, X ← X + V dt.
/// Velocities used by the forces are those at the start of the step.
TUMBLE_HD_INLINE void integrateTranslation(Vec3f F, float invMass, float dt, Vec3f* ioX, Vec3f* ioV) {
  const float s = invMass * dt;
  *ioV = *ioV + s * F;
  *ioX = *ioX + dt * *ioV;
}

/// Rotation as in the report: L ← L + T dt (forward Euler), then the exponential map
/// Q ← [cos(|Ω|dt/2), Ω/|Ω| sin(|Ω|dt/2)] ⊗ Q with Ω from the new L, renormalised.
/// Returns Ω of the new state (for the next step's particle velocities).
TUMBLE_HD_INLINE Vec3f integrateRotation(Vec3f T, const Sym3f& invInertia, float dt, Vec3f* ioL, Quatf* ioQ) {
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
  return angularVelocity(*ioQ, invInertia, *ioL);
}

}  // namespace tumble
