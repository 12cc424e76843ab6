// SPDX-License-Identifier: MIT
/// @file contact.hpp
/// Contact, ground and external forces of one particle (SPEC §2.3–2.5).
///
/// Antisymmetry: contactForces(i, j) is the exact negation of contactForces(j, i), bit for bit,
/// because every operation sees negated inputs (d = x_i − x_j, w = u_j − u_i) and IEEE + − * /
/// commute with negation. Summing each particle's forces in a fixed order therefore conserves
/// momentum to rounding, with no atomics.
///
/// Velocities at the contact point: the damping, shear and friction forces act at the contact
/// point, so they are computed from the velocity of the material there, u = v + Ω × (c − x),
/// not from the particle centre's v. With the centre's velocity, the couple of a friction force
/// could do positive work (a clump held by friction spun up without limit), and nothing could
/// roll. Single-sphere bodies do not rotate (Ω = 0), so for them u = v.
#pragma once
#include <cmath>
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/math.hpp"

namespace tumble {

/// Particle–particle coefficients as the kernels see them.
struct ContactCoeffs {
  float stiffness;  ///< k_s
  float damping;    ///< η
  float shear;      ///< k_t
};

/// The three contact forces that particle i receives from j, and where they act.
struct ContactForces {
  Vec3f repulsion, damping, shear;
  Vec3f lever;  ///< contact point − x_i = −n (r_i − δ/2): the middle of the overlap, common to i and j
};

/// Forces on particle i from an overlapping particle j (SPEC §2.3). `iBeforeJ` breaks the tie
/// for coincident centres: the normal is then +z for the lower index and −z for the other, so
/// the pair still separates and no NaN appears.
///
/// wi, wj: the angular velocities of the particles' bodies (the contact-point velocities use
/// them; pass zero for bodies that do not rotate).
TUMBLE_HD_INLINE ContactForces contactForces(Vec3f xi, Vec3f vi, Vec3f wi, float ri, Vec3f xj, Vec3f vj, Vec3f wj,
                                             float rj, bool iBeforeJ, const ContactCoeffs& c) {
  const Vec3f d = xi - xj;
  const float dist = std::sqrt(dot(d, d));
  Vec3f n;
  if (dist > 0.0f) {
    n = Vec3f{d.x / dist, d.y / dist, d.z / dist};
  } else {
    n = Vec3f{0.0f, 0.0f, iBeforeJ ? 1.0f : -1.0f};
  }
  const float delta = (ri + rj) - dist;
  // Levers from each centre to the contact point. Seen from j, n is negated, so both levers
  // (and the contact-point velocities) come out with the same bits: w is negated exactly.
  const Vec3f leverI = -(ri - 0.5f * delta) * n;
  const Vec3f leverJ = (rj - 0.5f * delta) * n;
  const Vec3f ui = vi + cross(wi, leverI);
  const Vec3f uj = vj + cross(wj, leverJ);
  const Vec3f w = uj - ui;
  const float wn = dot(w, n);
  ContactForces f;
  f.repulsion = (c.stiffness * delta) * n;
  f.damping = c.damping * w;
  f.shear = c.shear * (w - wn * n);
  f.lever = leverI;
  return f;
}

/// Sum of the three, in a fixed order.
///
/// Forces act at the contact point (the middle of the overlap), not at the particle centre:
/// the damping and shear forces are not central, and applied at the centres they would create
/// a spurious couple that breaks conservation of angular momentum. A clump particle therefore
/// also passes the couple lever × f to its body (SPEC §2.6 refined: T = Σ R u_i × f_i + Σ τ_i).
TUMBLE_HD_INLINE Vec3f total(const ContactForces& f) { return (f.repulsion + f.damping) + f.shear; }

/// Ground coefficients as the kernels see them.
struct GroundCoeffs {
  float height;
  float stiffness;             ///< k_g
  float tangentialStiffness;   ///< k_t,g of the stick spring
  float friction;              ///< μ
};

/// Normal and friction force of the ground on one particle.
struct GroundForces {
  Vec3f normal, friction;
  Vec3f lever;  ///< contact point − x: the bottom of the overlap, where the friction acts
};

/// Ground contact of a particle (SPEC §2.4): linear spring-dashpot along +z,
/// f_n = k_g δ − c v_z (c from the particle's elasticity, not clamped at zero), and Coulomb
/// friction regularised by a tangential stick spring (Cundall–Strack): the elongation ξ
/// (in/out: *tx, *ty) grows with the slip velocity, the trial force −k_t ξ − c v_t is capped at
/// μ max(f_n, 0), and ξ is rewound to match when the cap applies. A body below the friction
/// angle therefore sticks elastically instead of creeping. Out of contact, ξ is reset to zero.
///
/// omega: the body's angular velocity. Friction acts at the bottom of the overlap,
/// lever (0, 0, −(r − δ/2)), and its slip velocity is that point's: v + Ω × lever. The normal
/// component is unaffected (the lever is vertical).
TUMBLE_HD_INLINE GroundForces groundForces(Vec3f x, Vec3f vCentre, Vec3f omega, float r, float c,
                                           const GroundCoeffs& g, float dt, float* tx, float* ty) {
  GroundForces out{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}};
  const float delta = r - (x.z - g.height);
  if (!(delta > 0.0f)) {
    *tx = 0.0f;
    *ty = 0.0f;
    return out;
  }
  out.lever = Vec3f{0.0f, 0.0f, -(r - 0.5f * delta)};
  const Vec3f spin = cross(omega, out.lever);
  const Vec3f v{vCentre.x + spin.x, vCentre.y + spin.y, vCentre.z};
  const float fn = g.stiffness * delta - c * v.z;
  out.normal = Vec3f{0.0f, 0.0f, fn};
  float ex = *tx + v.x * dt;
  float ey = *ty + v.y * dt;
  float fx = -g.tangentialStiffness * ex - c * v.x;
  float fy = -g.tangentialStiffness * ey - c * v.y;
  const float limit = g.friction * (fn > 0.0f ? fn : 0.0f);
  const float f2 = fx * fx + fy * fy;
  if (f2 > limit * limit) {
    const float fmag = std::sqrt(f2);
    const float s = limit / fmag;
    fx *= s;
    fy *= s;
    if (g.tangentialStiffness > 0.0f) {
      ex = -(fx + c * v.x) / g.tangentialStiffness;
      ey = -(fy + c * v.y) / g.tangentialStiffness;
    }
  }
  *tx = ex;
  *ty = ey;
  out.friction = Vec3f{fx, fy, 0.0f};
  return out;
}

/// Gravity and the user pulls on a particle of mass m at x (SPEC §2.5); pulls are PullBits.
/// `centre` is the world origin in the integration frame ((0, 0, 0) unless the pipeline runs in
/// a local frame, LocalFrame); x − centre is exact for the default centre.
TUMBLE_HD_INLINE Vec3f externalForce(Vec3f x, float m, Vec3f gravity, float kx, float ky, float ks,
                                     std::uint32_t pulls, Vec3f centre) {
  Vec3f a = gravity;
  const float rx = x.x - centre.x, ry = x.y - centre.y;
  if (pulls & 1u) a.x -= kx * rx;
  if (pulls & 2u) a.y -= ky * ry;
  if (pulls & 4u) {
    a.x -= ks * ry;
    a.y += ks * rx;
  }
  return m * a;
}

}  // namespace tumble
