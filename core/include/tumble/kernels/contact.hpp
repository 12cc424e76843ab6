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
/// point, so they are computed from the velocity of the material there, u = V + Ω × (c − X),
/// not from the particle centre's. With the centre's velocity, the couple of a friction force
/// could do positive work (a clump held by friction spun up without limit), and nothing could
/// roll. Single-sphere bodies do not rotate (Ω = 0), so for them u = V.
#pragma once
#include <cmath>
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/kernels/cohesion.hpp"
#include "tumble/kernels/history.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/math.hpp"

namespace tumble {

/// Particle–particle coefficients as the kernels see them.
struct ContactCoeffs {
  float stiffness;  ///< k_s
  float damping;    ///< η
  float shear;      ///< k_t
};

/// The power a contact takes out of the bodies' motion (W; the energy tally, EnergyFlows): by
/// the normal dashpot, by the tangential force, and the tangential dashpot's part of the latter
/// (0 while the contact slides); and the forces on i of the two dashpots (the tangential one's
/// while the contact sticks, else 0).
struct ContactLoss {
  float normal, tangential, dashpot;
  Vec3f damping, drag;
};

/// A JKR neck's share of the energy tally (a contact stretched beyond touching, δ < 0): the
/// power its elastic force takes into the neck, F_el w_n (lost when the neck breaks), and that
/// force on i; zero otherwise. Apart from ContactLoss, which a larger size would cost every law
/// (ContactForces then no longer fits the compiler's scalar replacement: +1.7 % instructions for
/// hooke-history clumps, measured).
struct NeckFlow {
  float power = 0.0f;
  Vec3f force{0.0f, 0.0f, 0.0f};
};

/// The three contact forces that particle i receives from j, and where they act.
struct ContactForces {
  Vec3f repulsion, damping, shear;
  /// contact point − X_i (the centre of i's body): the arm of the forces' torque on that body.
  /// The contact point is the middle of the overlap, x_i − n (r_i − δ/2), common to i and j.
  Vec3f arm;
  Vec3f n;       ///< laws with history: the unit normal (from j to i)
  /// laws with history: the load that caps friction and rolling resistance, F_n along n
  /// (repulsion + damping, with cohesion the attraction's and its shift: Attraction).
  float normal;
  /// laws with history: the power the contact takes out of the bodies' motion (W, the forces on
  /// i dotted with w = u_j − u_i), for the energy tally (EnergyFlows): by the normal dashpot
  /// (g_n w_n²), by the tangential force (F_t · w_t), and the part of that by the tangential
  /// dashpot (g_t |w_t|² while the contact sticks; 0 once it slides). Unread outside the tally.
  ContactLoss loss;
};

/// One side of a contact as the forces see it: the particle's offset from its body's centre
/// (x − X, computed from the stored positions) and the body's velocity V and Ω.
struct ContactSide {
  Vec3f offset, v, omega;
};

/// The geometry and kinematics of a contact as i sees it: the unit normal n (from j to i), the
/// overlap δ, the arm of the forces on i's body (contact point − X_i; the contact point is the
/// middle of the overlap) and the velocity w of j's material relative to i's there.
struct ContactKinematics {
  Vec3f n;
  float delta;
  Vec3f arm;
  Vec3f w;
};

/// Contact kinematics of particle i and an overlapping particle j, given d = x_i − x_j and
/// |d|² from the overlap test (spheresOverlap). `iBeforeJ` breaks the tie for coincident
/// centres (|d| = 0): the normal is then +z for the lower scene index and −z for the other, so
/// the pair still separates and no NaN appears; it is not read otherwise.
///
/// w is the relative velocity of the two bodies' material at the contact point,
/// u = V + Ω × (c − X) on each side. kRotating false (no body rotates): Ω = 0 and the offsets
/// are 0, so u = V. Seen from j every output but δ is negated exactly.
template <bool kRotating>
TUMBLE_HD_INLINE ContactKinematics contactKinematics(Vec3f d, float d2, float ri, float rj, const ContactSide& si,
                                                     const ContactSide& sj, bool iBeforeJ) {
  const float dist = std::sqrt(d2);
  ContactKinematics k;
  if (dist > 0.0f) {
    const float inv = 1.0f / dist;
    k.n = d * inv;
  } else {
    k.n = Vec3f{0.0f, 0.0f, iBeforeJ ? 1.0f : -1.0f};
  }
  k.delta = (ri + rj) - dist;
  // Levers from each centre to the contact point. Seen from j, n is negated, so both levers
  // (and the contact-point velocities) come out with the same bits: w is negated exactly.
  const Vec3f leverI = -(ri - 0.5f * k.delta) * k.n;
  const Vec3f leverJ = (rj - 0.5f * k.delta) * k.n;
  if (kRotating) {
    k.arm = si.offset + leverI;
    const Vec3f armJ = sj.offset + leverJ;
    k.w = pointVelocity(sj.v, sj.omega, armJ) - pointVelocity(si.v, si.omega, k.arm);
  } else {
    k.arm = leverI;
    k.w = sj.v - si.v;
  }
  return k;
}

/// Forces of the report's law on particle i from an overlapping particle j (SPEC §2.3):
/// f_s = k_s δ n, f_d = η w, f_t = k_t (w − (w·n) n); arguments as contactKinematics().
template <bool kRotating>
TUMBLE_HD_INLINE ContactForces contactForces(Vec3f d, float d2, float ri, float rj, const ContactSide& si,
                                             const ContactSide& sj, bool iBeforeJ, const ContactCoeffs& c) {
  const ContactKinematics k = contactKinematics<kRotating>(d, d2, ri, rj, si, sj, iBeforeJ);
  ContactForces f;
  f.arm = k.arm;
  const float wn = dot(k.w, k.n);
  f.repulsion = (c.stiffness * k.delta) * k.n;
  f.damping = c.damping * k.w;
  f.shear = c.shear * (k.w - wn * k.n);
  return f;
}

/// Coefficients of hooke-history as the kernels see them.
struct HistoryCoeffs {
  float kn;      ///< normal stiffness [N/m]
  float kt;      ///< tangential stiffness [N/m]
  float gammaN;  ///< normal damping per effective mass [1/s]
  float gammaT;  ///< tangential damping per effective mass [1/s]
  float mu;      ///< Coulomb friction coefficient
  float cohesion = 0.0f;  ///< k_c or γ of every pair (Cohesion; 0: none)
};

/// The tangential force of a contact with history on particle i (Cundall–Strack), shared by
/// hooke-history and hertz-mindlin: n the unit normal (from j to i), w_t the tangential part of
/// the relative velocity w, F_n the normal force, k_t the tangential stiffness [N/m], g_t the
/// tangential dashpot [N s/m], *xi (in/out) i's sliding displacement relative to j:
///   ξ ← ξ − w_t dt, then ξ ← ξ − (ξ·n) n
///   F_t = g_t w_t − k_t ξ, capped at μ |F_n|; when capped, ξ ← (g_t w_t − F_t)/k_t.
/// Seen from j every input but F_n is negated, and so are F_t and ξ. *slides: whether the cap
/// applied.
TUMBLE_HD_INLINE Vec3f historyShear(Vec3f n, Vec3f wt, float fn, float kt, float gt, float mu, float dt, Vec3f* xi,
                                    bool* slides) {
  Vec3f x = *xi - dt * wt;
  x = x - dot(x, n) * n;
  const Vec3f drag = gt * wt;
  Vec3f ft = drag - kt * x;
  const float limit = mu * (fn < 0.0f ? -fn : fn);
  const float f2 = dot(ft, ft);
  *slides = f2 > limit * limit;
  if (*slides) {
    ft = (limit / std::sqrt(f2)) * ft;
    if (kt > 0.0f) x = (1.0f / kt) * (drag - ft);
  }
  *xi = x;
  return ft;
}

/// A contact with history from its kinematics, its elastic normal force (k_n δ − F_c with a
/// cohesive contact's attraction, cohesion.hpp; JKR's), dashpots g_n and g_t [N s/m] and the
/// shift of its friction load: F_n = elastic + g_n w_n along n (the repulsion: elastic), the
/// shear from historyShear() capped by μ |F_n + shift|.
TUMBLE_HD_INLINE ContactForces historyContact(const ContactKinematics& k, float elastic, float kt, float gn, float gt,
                                              float mu, float dt, Vec3f* xi, float shift) {
  ContactForces f;
  f.arm = k.arm;
  const float wn = dot(k.w, k.n);
  const Vec3f wt = k.w - wn * k.n;
  const float viscous = gn * wn;
  f.repulsion = elastic * k.n;
  f.damping = viscous * k.n;
  f.n = k.n;
  f.normal = (elastic + viscous) + shift;
  bool slides;
  f.shear = historyShear(k.n, wt, f.normal, kt, gt, mu, dt, xi, &slides);
  const Vec3f drag = slides ? Vec3f{0.0f, 0.0f, 0.0f} : gt * wt;
  f.loss = ContactLoss{viscous * wn, dot(f.shear, wt), dot(drag, wt), f.damping, drag};
  return f;
}

/// Forces of hooke-history (LAMMPS gran/hooke/history) on particle i from an overlapping
/// particle j, from the contact's kinematics (contactKinematics()), meff = M_i M_j / (M_i + M_j)
/// of the two bodies, *xi as historyShear(), a the attraction of a cohesive contact:
///   F_n = (k_n δ − F_c + m_eff γ_n w_n) n                         (repulsion, damping)
///   F_t = m_eff γ_t w_t − k_t ξ, capped at μ |F_n + shift|         (the shear)
/// Seen from j every input is negated, so are the forces and ξ: the two sides of a contact keep
/// exact negations of one history.
TUMBLE_HD_INLINE ContactForces hookeHistoryForces(const ContactKinematics& k, float meff, const HistoryCoeffs& c,
                                                  float dt, Vec3f* xi, Attraction a) {
  return historyContact(k, c.kn * k.delta - a.pull, c.kt, meff * c.gammaN, meff * c.gammaT, c.mu, dt, xi, a.shift);
}

/// Hertz–Mindlin coefficients of a pair of materials (materialPair()), or of a material and
/// the ground: what the kernels need of Y*, G* and the restitution.
struct HertzPair {
  float ystar;  ///< Y* = 1 / ((1 − ν₁²)/E₁ + (1 − ν₂²)/E₂) [Pa]
  float gstar;  ///< G* = 1 / (2(2 − ν₁)(1 + ν₁)/E₁ + 2(2 − ν₂)(1 + ν₂)/E₂) [Pa]
  float damp;   ///< −2 √(5/6) β, β = ln e / √(ln² e + π²) (0 for e = 1)
  float mu;     ///< Coulomb μ of the pair
  float muR;    ///< rolling resistance μ_r of the pair (0: none)
  float cohesion = 0.0f;  ///< k_c or γ of the pair (Cohesion; 0: none)
};

/// Where the pair of materials a, b sits in a table of m materials, (m + 1)² entries
/// (World::materialPairs); b = m: material a on the ground.
TUMBLE_HD_INLINE std::uint32_t materialPairIndex(std::uint32_t a, std::uint32_t b, std::uint32_t m) {
  return a * (m + 1u) + b;
}

/// Particle i's material from a column that is nullptr when the scene has a single material.
TUMBLE_HD_INLINE std::uint32_t materialOf(const std::uint16_t* material, std::uint32_t i) {
  return material ? material[i] : 0u;
}

/// Hertz–Mindlin (LIGGGHTS `hertz` with tangential history) on particle i from an overlapping
/// particle j or the ground, from the contact's kinematics, its effective radius R* and mass m*:
///   S_n = 2 Y* √(R* δ),  S_t = 8 G* √(R* δ)
///   F_n = (⅔ S_n δ + g_n w_n) n,  g_n = −2 √(5/6) β √(S_n m*)   (= 4/3 Y* √R* δ^{3/2} elastic)
///   k_t = S_t,  g_t = −2 √(5/6) β √(S_t m*), the shear as historyShear() with μ;
/// a cohesive contact's attraction a as historyContact().
/// Every coefficient depends on the pair only through symmetric quantities, so the forces seen
/// from j are the exact negations.
TUMBLE_HD_INLINE ContactForces hertzMindlinForces(const ContactKinematics& k, float reff, float meff,
                                                  const HertzPair& c, float dt, Vec3f* xi, Attraction a) {
  const float root = std::sqrt(reff * k.delta);
  const float sn = (2.0f * c.ystar) * root, st = (8.0f * c.gstar) * root;
  const float kn = (2.0f / 3.0f) * sn;
  return historyContact(k, kn * k.delta - a.pull, st, c.damp * std::sqrt(sn * meff), c.damp * std::sqrt(st * meff),
                        c.mu, dt, xi, a.shift);
}

/// hertzMindlinForces() under JKR (j = jkrContact() of the contact, held): the elastic force
/// JKR's, the stiffnesses S_n = 2 Y* a, S_t = 8 G* a at JKR's contact radius a (also in a neck,
/// δ < 0), the friction load shifted by 3 π γ R*; ξ left marked as held (heldSpring()). In a
/// neck (δ < 0) *neck gets its flow (NeckFlow; left alone otherwise).
TUMBLE_HD_INLINE ContactForces jkrForces(const ContactKinematics& k, float meff, const HertzPair& c, float dt,
                                         Vec3f* xi, const JkrContact& j, NeckFlow* neck) {
  const float sn = (2.0f * c.ystar) * j.a, st = (8.0f * c.gstar) * j.a;
  const ContactForces f = historyContact(k, j.elastic, st, c.damp * std::sqrt(sn * meff),
                                         c.damp * std::sqrt(st * meff), c.mu, dt, xi, j.shift);
  *xi = heldSpring(*xi);
  if (k.delta < 0.0f) *neck = NeckFlow{j.elastic * dot(k.w, k.n), f.repulsion};
  return f;
}

/// Sum of the three, in a fixed order.
///
/// Forces act at the contact point (the middle of the overlap), not at the particle centre:
/// the damping and shear forces are not central, and applied at the centres they would create
/// a spurious couple that breaks conservation of angular momentum. Their torque on the body is
/// arm × f with arm = contact point − X.
TUMBLE_HD_INLINE Vec3f total(const ContactForces& f) { return (f.repulsion + f.damping) + f.shear; }

/// Rolling resistance, constant-torque model (Zhou et al. 1999, "model A"): a pure torque on i
///   M_i = −min(μ_r R* |F_n|, I* |ω_r| / dt) ω_r / |ω_r|,  ω_r = (ω_i − ω_j) − ((ω_i − ω_j)·n) n
/// against the rolling of i on j (the twist about n is left alone), j receiving −M_i; R* and m*
/// are the effective radius and mass of the pair and I* = 2/5 m* R*². The cap I* |ω_r| / dt
/// keeps the torque from reversing the relative rolling within one step, which would make it
/// flip sign every step about rest (the model's chatter): for two equal spheres (I* = I/8, both
/// turned) it removes at most a quarter of ω_r per step, so rolling stops over a few steps. With
/// ω_j = 0 and n = +z (R* = r, m* = M) it is the ground's, and then it stops the rolling within
/// one step. Seen from j every input is negated, and so is the torque.
TUMBLE_HD_INLINE Vec3f rollingTorque(Vec3f omegaI, Vec3f omegaJ, Vec3f n, float fn, float reff, float meff, float muR,
                                     float dt) {
  const Vec3f rel = omegaI - omegaJ;
  const Vec3f wr = rel - dot(rel, n) * n;
  const float w2 = dot(wr, wr);
  if (!(w2 > 0.0f)) return Vec3f{0.0f, 0.0f, 0.0f};
  const float w = std::sqrt(w2);
  const float limit = muR * reff * (fn < 0.0f ? -fn : fn);
  const float stop = (0.4f * meff * reff * reff) * w / dt;
  return (-(limit < stop ? limit : stop) / w) * wr;
}

/// Ground coefficients as the kernels see them.
struct GroundCoeffs {
  float height;
  float stiffness;             ///< k_g
  float tangentialStiffness;   ///< k_t,g of the stick spring
  float friction;              ///< μ
  float rollingFriction;       ///< μ_r (0: none; laws that turn spheres only)
  float cohesion = 0.0f;       ///< hooke-history: k_c or γ of the sphere–plane pairs (Cohesion; 0: none)
};

/// Depth δ = r − (z − h) of a particle below the ground's surface: in contact when δ > 0.
TUMBLE_HD_INLINE float groundDepth(Vec3f x, float r, const GroundCoeffs& g) { return r - (x.z - g.height); }

/// Normal and friction force of the ground on one particle.
struct GroundForces {
  Vec3f normal, friction;
  Vec3f arm;  ///< contact point − X: the bottom of the overlap, where both act
  /// The power the contact takes out of the particle's motion relative to the plane (as
  /// ContactForces::loss; the energy tally only).
  ContactLoss loss;
};

/// Ground contact of a particle (SPEC §2.4): linear spring-dashpot along +z,
/// f_n = k_g δ − c u_z (c from the particle's elasticity, not clamped at zero), and Coulomb
/// friction regularised by a tangential stick spring (Cundall–Strack): the elongation ξ
/// (in/out: *tx, *ty) grows with the slip velocity, the trial force −k_t ξ − c u_t is capped at
/// μ max(f_n, 0), and ξ is rewound to match when the cap applies. A body below the friction
/// angle therefore sticks elastically instead of creeping. Out of contact, ξ is reset to zero.
///
/// side: the particle's offset from its body's centre and the body's V and Ω. The forces act
/// at the bottom of the overlap, lever (0, 0, −(r − δ/2)) from the centre, and u is the
/// velocity of the material there. kRotating false: u = V.
///
/// A cohesive contact (a: its attraction, cohesion.hpp; {0, 0} without) adds −F_c to f_n and
/// caps the friction at μ max(f_n + shift, 0).
///
/// Called only for a particle in contact, groundDepth(x, r, g) > 0; out of contact the caller
/// resets ξ to zero.
template <bool kRotating>
TUMBLE_HD_INLINE GroundForces groundForces(Vec3f x, float r, const ContactSide& side, float c, const GroundCoeffs& g,
                                           float dt, float* tx, float* ty, Attraction a = Attraction{0.0f, 0.0f}) {
  GroundForces out{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {}};
  const float delta = groundDepth(x, r, g);
  const Vec3f lever{0.0f, 0.0f, -(r - 0.5f * delta)};
  Vec3f v;
  if (kRotating) {
    out.arm = side.offset + lever;
    v = pointVelocity(side.v, side.omega, out.arm);
  } else {
    out.arm = lever;
    v = side.v;
  }
  const float fn = (g.stiffness * delta - a.pull) - c * v.z;
  out.normal = Vec3f{0.0f, 0.0f, fn};
  float ex = *tx + v.x * dt;
  float ey = *ty + v.y * dt;
  float fx = -g.tangentialStiffness * ex - c * v.x;
  float fy = -g.tangentialStiffness * ey - c * v.y;
  const float load = fn + a.shift;
  const float limit = g.friction * (load > 0.0f ? load : 0.0f);
  const float f2 = fx * fx + fy * fy;
  const bool slides = f2 > limit * limit;
  if (slides) {
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
  // The plane's material at rest here (a moving wall's velocity is subtracted from side's): w = −v.
  const Vec3f drag = slides ? Vec3f{0.0f, 0.0f, 0.0f} : Vec3f{-c * v.x, -c * v.y, 0.0f};
  out.loss = ContactLoss{c * (v.z * v.z), -(fx * v.x + fy * v.y), -(drag.x * v.x + drag.y * v.y),
                         Vec3f{0.0f, 0.0f, -c * v.z}, drag};
  return out;
}

/// Hertz–Mindlin contact of a particle with the ground (hertzMindlinForces() on a plane with
/// normal +z: R* = r, m* = the body's mass M, the pair c of the particle's material and the
/// ground's). The forces act at the bottom of the overlap, as groundForces(); the ground's
/// material is at rest, so w = −u there. *tx, *ty (in/out) are ξ, the particle's sliding
/// displacement on the ground, with groundForces()' sign (F_t = −k_t ξ − g_t u_t); a: the
/// attraction of a cohesive contact (hertzMindlinForces()). Called only for a particle in
/// contact; out of contact the caller resets ξ to zero.
template <bool kRotating>
TUMBLE_HD_INLINE GroundForces hertzGroundForces(Vec3f x, float r, const ContactSide& side, float mass,
                                                const HertzPair& c, const GroundCoeffs& g, float dt, float* tx,
                                                float* ty, Attraction a, const JkrContact* jkr = nullptr,
                                                NeckFlow* neck = nullptr) {
  ContactKinematics k;
  k.n = Vec3f{0.0f, 0.0f, 1.0f};
  k.delta = groundDepth(x, r, g);
  const Vec3f lever{0.0f, 0.0f, -(r - 0.5f * k.delta)};
  k.arm = kRotating ? side.offset + lever : lever;
  k.w = -(kRotating ? pointVelocity(side.v, side.omega, k.arm) : side.v);
  Vec3f xi{*tx, *ty, 0.0f};
  const ContactForces f =
      jkr != nullptr ? jkrForces(k, mass, c, dt, &xi, *jkr, neck) : hertzMindlinForces(k, r, mass, c, dt, &xi, a);
  *tx = xi.x;
  *ty = xi.y;
  if (jkr != nullptr) heldPlaneSpring(tx, ty);
  return GroundForces{f.repulsion + f.damping, f.shear, f.arm, f.loss};
}

/// The user pulls on a particle of mass m at x (SPEC §2.5); pulls are PullBits (0: none, and
/// the caller skips the call). `centre` is the world origin in the integration frame
/// ((0, 0, 0) unless the pipeline runs in a local frame, LocalFrame); x − centre is exact for
/// the default centre. Gravity is not a pull: it acts on each body as M g, at its centre of
/// mass (no torque), which is what Σ m_i g over the particles is without its rounding.
TUMBLE_HD_INLINE Vec3f pullForce(Vec3f x, float m, float kx, float ky, float ks, std::uint32_t pulls, Vec3f centre) {
  Vec3f a{0.0f, 0.0f, 0.0f};
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
