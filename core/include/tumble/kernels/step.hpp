// SPDX-License-Identifier: MIT
/// @file step.hpp
/// The per-element bodies of the step's stages (SPEC §2), written once for both pipelines:
/// the CPU calls them from TBB loops (fused into one pass per body), the CUDA pipeline from
/// two-line __global__ wrappers (one kernel per stage: particleForce per particle, then
/// finishBody per body). Each function writes only element i's
/// (or body k's) outputs and sums in a fixed order that belongs to the physics, not to how
/// contacts were found: a particle sums its contacts in ascending scene index of the partner
/// (the candidate list's order), then the planes (the ground, then the walls), then gravity and pulls; a body sums its
/// particles in their order within the body. So the results do not depend on the scheduling,
/// the detection settings, the skin or the internal numbering.
#pragma once
#include <cfloat>
#include <cstddef>
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/kernels/contact.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/energy.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/kernels/mesh.hpp"
#include "tumble/kernels/overlap.hpp"
#include "tumble/kernels/periodic.hpp"
#include "tumble/kernels/wall.hpp"
#include "tumble/math.hpp"
#include "tumble/scene.hpp"
#include "tumble/soa.hpp"

namespace tumble {

/// Scene constants of the force stage.
struct ForceParams {
  ContactCoeffs contact;
  GroundCoeffs ground;    ///< the ground's (StepView::planes[0].coeffs when hasGround), for its test
  Vec3f gravity;
  float pullX, pullY, pullSwirl;
  Vec3f pullCentre;
  float dt;
  std::uint32_t pulls;
  HistoryCoeffs history;  ///< hooke-history only
  float rollingFriction;  ///< μ_r between particles (0: none; hooke-history only)
  bool hasGround;         ///< the first plane is the ground (StepView::planes[0])
  bool hasWalls;          ///< planes after the ground (wallContacts())
  /// The contacts' cohesion (laws with history; its coefficients: HistoryCoeffs::cohesion,
  /// GroundCoeffs::cohesion, HertzPair::cohesion); None: the kernels read nothing more.
  Cohesion cohesion;
};

/// The force-stage constants of a scene with the given pulls on (host side).
inline ForceParams makeForceParams(const Scene& p, std::uint32_t pulls) {
  const float kt = p.ground.tangentialStiffness > 0.0f ? p.ground.tangentialStiffness : p.ground.stiffness * (2.0f / 7.0f);
  return ForceParams{ContactCoeffs{p.contact.stiffness, p.contact.damping, p.contact.shear},
                     GroundCoeffs{p.ground.height, p.ground.stiffness, kt, p.ground.friction, p.groundRollingFriction(),
                                  p.cohesionOf(p.ground)},
                     p.gravity,
                     p.pulls.x,
                     p.pulls.y,
                     p.pulls.swirl,
                     p.pulls.centre,
                     p.dt,
                     pulls,
                     HistoryCoeffs{p.contact.stiffness,
                                   p.contact.tangentialStiffness > 0.0f ? p.contact.tangentialStiffness
                                                                        : p.contact.stiffness * (2.0f / 7.0f),
                                   p.contact.gammaN, p.contact.gammaT >= 0.0f ? p.contact.gammaT : 0.5f * p.contact.gammaN,
                                   p.contact.friction, p.contact.cohesion == Cohesion::None ? 0.0f : p.contact.cohesionValue},
                     p.contact.rollingFriction,
                     p.ground.enabled,
                     !p.walls.empty(),
                     p.contact.law == ContactLaw::Report ? Cohesion::None : p.contact.cohesion};
}

/// Debug capture (internal numbering, 3 floats per particle each): the five forces
/// (repulsion, damping, shear, ground, friction) and the velocity of the particle's centre at
/// the start of the step; and per entry of the list the step reads, its contact (ContactForce,
/// scene indices; kNoContact where the entry did not touch).
struct DebugForcesView {
  float* f[5];
  float* v;
  ContactForce* contact;
};

/// Entry e's capture of the contact (i at pi, j at pj; d = x_i − x_j, |d|² = d2 as the predicate
/// computed them) whose force on i was f, split along the unit normal d / |d|, taken in double so
/// that it is one to a float's rounding even where |d|² is a denormal float (at coincident
/// centres the contact law's ±z, + for the lower scene index: contactKinematics()).
TUMBLE_HD_INLINE ContactForce capturedContact(const StepView& v, std::uint32_t i, const PosRow& pi, std::uint32_t j,
                                              Vec3f d, float d2, Vec3f f) {
  const float dist = sqrtf(d2);
  const double len = sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
  const Vec3f n = len > 0.0 ? Vec3f{float(d.x / len), float(d.y / len), float(d.z / len)}
                            : Vec3f{0.0f, 0.0f, v.orig[i] < v.orig[j] ? 1.0f : -1.0f};
  const float fn = dot(f, n);
  return ContactForce{v.orig[i], v.orig[j], n, fn, f - fn * n, pi.r + v.pos[j].r - dist};
}

/// Particle positions from their body's state (SPEC §2.1), x = X + R u (R = b.rot), for the
/// particles first..first+count of body b, with their radii; their displacements since the
/// skin test's reference (buildPos) are added to *drift (pass nullptrs for neither). Single-sphere scenes
/// (kClumps false): x = X. kPeriodic: the displacements are minimum images in `box`, so that a
/// body's wrap does not count as motion.
template <bool kClumps, bool kPeriodic = false>
TUMBLE_HD_INLINE void bodyParticles(const BodyRow& b, const OwnRow* own, const float* radius, const PosRow* buildPos,
                                    PosRow* outPos, Drift* drift, const PeriodicBox& box = PeriodicBox{}) {
  const Mat3f& R = b.rot;
  for (std::uint32_t i = b.first, e = b.first + b.count; i < e; ++i) {
    const Vec3f x = kClumps ? particlePosition(b.x, R, own[i].u) : b.x;
    const PosRow p{x.x, x.y, x.z, radius[i]};
    outPos[i] = p;
    if (buildPos) addParticleDisplacement<kPeriodic>(*drift, p, buildPos[i], box);
  }
}

/// What the force stage reads of a particle's body: the lever R u from the centre (the same
/// expression as its position, so that it does not depend on where the body is), V and Ω.
TUMBLE_HD_INLINE ContactSide sideOf(const BodyRow& b, Vec3f u) { return ContactSide{mul(b.rot, u), b.v, b.omega}; }

/// Particle i's force and torque about its body's centre in one step, and its number of
/// touching contacts.
struct ParticleForce {
  Vec3f f, t;
  std::uint32_t contacts;
};

/// The energy tally's sums over a particle's (or a body's) contacts in one step (kDebug): their
/// EnergyFlows at the velocities the step starts from, and for each kind that dissipates (the
/// normal dashpots, the tangential dashpots, friction) the forces and torques about the body's
/// centre that those contacts put on the body. With the body's change of velocity over the step
/// they move the flows to the middle of the step (stepBody()), where the change of kinetic
/// energy is exactly the force times the mean velocity: without that, the tally would count
/// |F|² dt / 2m too much each step (a drift of the balance with the energy dissipated).
struct EnergyWork {
  EnergyFlows flows;
  Vec3f f[4], t[4];
};
TUMBLE_HD_INLINE EnergyWork noWork() {
  EnergyWork w;
  w.flows = noFlows();
  for (int c = 0; c < 4; ++c) w.f[c] = w.t[c] = Vec3f{0.0f, 0.0f, 0.0f};
  return w;
}
TUMBLE_HD_INLINE void addWork(EnergyWork& a, const EnergyWork& b) {
  addFlows(a.flows, b.flows);
  for (int c = 0; c < 4; ++c) {
    a.f[c] += b.f[c];
    a.t[c] += b.t[c];
  }
}

/// One contact's share of *w: `share` of its losses (½ for a pair, which both sides count) and
/// of a JKR neck's power, and whole, its forces on this particle by kind (loss: the dashpots',
/// shear − drag for friction; the neck's elastic force, neckForce), their torques at `arm`, and
/// the rolling resistance's torque `roll` and power `rollLoss`.
template <bool kClumps>
TUMBLE_HD_INLINE void addContactWork(EnergyWork& w, const ContactLoss& l, Vec3f damping, Vec3f drag, float neck,
                                     Vec3f neckForce, Vec3f shear, Vec3f arm, Vec3f roll, float rollLoss, float share) {
  w.flows.normal += share * l.normal;
  w.flows.tangential += share * l.dashpot;
  w.flows.friction += share * ((l.tangential - l.dashpot) + rollLoss);
  w.flows.cohesion += share * neck;
  const Vec3f f[4] = {damping, drag, shear - drag, neckForce};
  for (int c = 0; c < 4; ++c) {
    w.f[c] += f[c];
    if (kClumps) w.t[c] += cross(arm, f[c]);
  }
  if (kClumps) w.t[2] += roll;
}

/// Whether a sphere that does not touch a plane (the ground, a wall) holds to it by a JKR neck
/// that may still hold (its plane spring marked, heldPlaneSpring()): planeContact() then
/// decides, releasing it past the neck's end. Other laws and models: never.
template <ContactLaw kLaw>
TUMBLE_HD_INLINE bool heldPlane(const ForceParams& fp, float tx, float ty) {
  if constexpr (kLaw == ContactLaw::HertzMindlin) return fp.cohesion == Cohesion::Jkr && !isZeroPlaneSpring(tx, ty);
  return false;
}

/// Particle i (of body `self`, radius r, its contact side `side`) in contact with wall k, at xl
/// in the wall's frame w (axis kAxis, see wall.hpp: the plane's own or, for a revolved wall or a
/// mesh, that of its surface at the nearest point): the ground's contact in that frame, turned
/// back to the world frame, with the stick spring (*tx, *ty, along w's t1, t2) updated; its
/// force, torque and rolling torque are added to *out, and the forces returned (for the debug
/// capture). When the wall moves (w.moving), the velocities are relative to its material at the
/// contact point. work (the energy tally; nullptr: none) gains the contact's (EnergyWork).
template <int kAxis, bool kClumps, ContactLaw kLaw>
TUMBLE_HD_INLINE GroundForces planeContact(const StepView& v, const ForceParams& fp, const Wall& w, std::uint32_t k,
                                           std::uint32_t i, Vec3f xi, Vec3f xl, float r, const BodyRow& self,
                                           const ContactSide& side, float* tx, float* ty, ParticleForce* out,
                                           EnergyWork* work) {
  ContactSide sl = toWall<kAxis>(w, side);
  Vec3f wallOmega{0.0f, 0.0f, 0.0f}, wallV{0.0f, 0.0f, 0.0f};
  if constexpr (kAxis != kGroundFrame) {  // the ground does not move
    if (w.moving) {  // w.n is the contact's normal; the wall's axis is planes[k]'s
      const Wall& wall = v.planes[k];
      // The material's velocity where the forces act, the bottom of the overlap (groundForces()).
      const Vec3f p = xi - (r - 0.5f * groundDepth(xl, r, w.coeffs)) * w.n;
      wallV = wallVelocity(wall, p);
      sl.v = sl.v - toWall<kAxis>(w, wallV);
      wallOmega = wall.omega * wall.n;
    }
  }
  float sx = *tx, sy = *ty;  // locals: the spring is read once and written once
  GroundForces g;
  [[maybe_unused]] NeckFlow neck;  // the tally's (a JKR neck)
  float muR;
  // A cohesive contact's attraction (cohesion.hpp), a plane's R* the sphere's radius.
  const auto pull = [&](float value) {
    if (fp.cohesion == Cohesion::None) return Attraction{0.0f, 0.0f};
    const float delta = groundDepth(xl, r, w.coeffs);
    return attraction(fp.cohesion, value, planeCrossingRadius2(delta, r), r);
  };
  Attraction att;
  if constexpr (kLaw == ContactLaw::HertzMindlin) {
    const HertzPair& hp = v.planeHertz[k * v.numMaterials + materialOf(v.material, i)];
    if (fp.cohesion == Cohesion::Jkr) {
      const JkrContact jc = jkrContact(groundDepth(xl, r, w.coeffs), r, hp.ystar, hp.cohesion);
      if (!jc.held) {  // a neck past its end (heldPlane()): released, no contact
        *tx = 0.0f;
        *ty = 0.0f;
        return GroundForces{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {}};
      }
      att = Attraction{0.0f, jc.shift};
      g = hertzGroundForces<kClumps>(xl, r, sl, 1.0f / self.invMass, hp, w.coeffs, fp.dt, &sx, &sy, att, &jc, &neck);
    } else {
      att = pull(hp.cohesion);
      g = hertzGroundForces<kClumps>(xl, r, sl, 1.0f / self.invMass, hp, w.coeffs, fp.dt, &sx, &sy, att);
    }
    muR = hp.muR;
  } else {
    const float c = k == 0 ? v.own[i].groundDamping : v.planeDamping[std::size_t(k - 1) * v.numParticles + i];
    att = pull(w.coeffs.cohesion);
    g = groundForces<kClumps>(xl, r, sl, c, w.coeffs, fp.dt, &sx, &sy, att);
    muR = w.coeffs.rollingFriction;
  }
  *tx = sx;
  *ty = sy;
  const float fn = g.normal.z + att.shift;  // the load that caps the rolling resistance, as the friction's
  g = GroundForces{fromWall<kAxis>(w, g.normal), fromWall<kAxis>(w, g.friction), fromWall<kAxis>(w, g.arm), g.loss};
  const Vec3f fg = g.normal + g.friction;
  out->f += fg;
  if (kClumps) out->t += cross(g.arm, fg);
  Vec3f roll{0.0f, 0.0f, 0.0f};
  if (kClumps && muR > 0.0f) {
    roll = rollingTorque(side.omega, wallOmega, w.n, fn, r, 1.0f / self.invMass, muR, fp.dt);
    out->t += roll;
  }
  if (work != nullptr) {  // the wall's material moves at wallV, turns at wallOmega
    addContactWork<kClumps>(*work, g.loss, fromWall<kAxis>(w, g.loss.damping), fromWall<kAxis>(w, g.loss.drag),
                            neck.power, fromWall<kAxis>(w, neck.force), g.friction, g.arm, roll,
                            -dot(roll, side.omega - wallOmega), 1.0f);
    work->flows.wall += dot(fg, wallV) + dot(roll, wallOmega);
  }
  return g;
}

/// The mesh walls on particle i, after the other walls: each triangle of its candidate row, in
/// ascending triangle index, that meshHit() counts meets it as a plane through its nearest
/// point (planeContact() in the frame there: n from that point to the centre, t1, t2 from
/// perpendicularPair(), the triangle's wall's coefficients). Its stick spring is that of the
/// (particle, triangle) entry, kept as a vector in the integration frame and projected on the
/// contact's tangent plane each step, so that a contact that moves from a face to an edge of
/// the same triangle keeps it; an entry that does not count releases it (a contact that passes
/// to a neighbouring triangle starts afresh there).
///
/// kPosed (some mesh wall moves, v.mesh.poses): each triangle meets the centre as its wall sees
/// it (meshPoint(): in the frame of a posed mesh), the normal is turned back into the run's
/// frame, and a moving wall's material velocity at the contact point enters as for the other
/// walls (planeContact(): v + ω × (p − pivot now), Wall of the mesh's plane). Without kPosed
/// the meshes do not move and this is the code of a static mesh, instruction for instruction.
template <bool kClumps, ContactLaw kLaw, bool kPosed = false>
TUMBLE_HD_INLINE void meshWallContacts(const StepView& v, const ForceParams& fp, const BodyRow& self, std::uint32_t i,
                                       Vec3f xi, float r, ContactSide& side, bool& haveSide, ParticleForce* out,
                                       GroundForces* gf, bool& anyPlane, EnergyWork* work) {
  const MeshListView& l = v.meshList;
  // The centre in the frame of the last entry's wall (a row's triangles come wall by wall).
  [[maybe_unused]] std::uint32_t seen = ~0u;
  [[maybe_unused]] Vec3f xm = xi;
  for (std::uint32_t e = l.offsets[i]; e < l.offsets[i + 1]; ++e) {
    const std::uint32_t t = l.tri[e];
    if constexpr (kPosed) {
      const std::uint32_t wall = v.mesh.tri[t].wall;
      if (wall != seen) {
        seen = wall;
        xm = meshPoint(v.mesh, wall, xi);
      }
    }
    const MeshHit h = meshHit(v.mesh, t, kPosed ? xm : xi, r);
    if (!h.counts) {  // not a contact of this triangle: its spring is released
      if (!isZeroSpring(l.hist[e])) l.hist[e] = Vec3f{0.0f, 0.0f, 0.0f};
      continue;
    }
    if (!haveSide) {
      side = sideOf(self, v.own[i].u);
      haveSide = true;
    }
    const std::uint32_t k = v.mesh.tri[t].wall;
    Wall f = v.planes[k];
    f.n = h.p.n;
    if constexpr (kPosed) {  // the normal back from a posed mesh's frame
      const MeshPose& pose = v.mesh.poses[k];
      if (pose.posed != 0u) f.n = mul(pose.rot, h.p.n);
    }
    const float n3[3] = {f.n.x, f.n.y, f.n.z};
    float a[3], b[3];
    perpendicularPair(n3, a, b);
    f.t1 = Vec3f{a[0], a[1], a[2]};
    f.t2 = Vec3f{b[0], b[1], b[2]};
    f.axis = kGeneralPlane;
    f.sign = 1.0f;
    f.coeffs.height = 0.0f;
    if constexpr (!kPosed) f.moving = 0u;  // (posed: the mesh's plane says whether it moves)
    const Vec3f xs = l.hist[e];
    float tx = dot(xs, f.t1), ty = dot(xs, f.t2);
    const GroundForces g = planeContact<-1, kClumps, kLaw>(v, fp, f, k, i, xi, Vec3f{0.0f, 0.0f, h.p.dist}, r, self,
                                                           side, &tx, &ty, out, work);
    l.hist[e] = tx * f.t1 + ty * f.t2;
    gf->normal = anyPlane ? gf->normal + g.normal : g.normal;
    gf->friction = anyPlane ? gf->friction + g.friction : g.friction;
    anyPlane = true;
  }
}

/// The walls (after the ground) on particle i, in their order, then the mesh walls'
/// triangles (meshWallContacts(), kPosed when a mesh wall moves); *gf (debug) gains their
/// forces, *work (the energy tally; nullptr: none) their EnergyWork. Not inlined: the loop
/// stays out of the force pass of a scene without walls.
template <bool kClumps, ContactLaw kLaw, bool kPosedMesh = false>
TUMBLE_HD_NOINLINE void wallContacts(const StepView& v, const ForceParams& fp, const BodyRow& self, std::uint32_t i,
                                     Vec3f xi, float r, ParticleForce* out, GroundForces* gf, bool anyPlane,
                                     EnergyWork* work) {
  ContactSide side{{0.0f, 0.0f, 0.0f}, self.v, {0.0f, 0.0f, 0.0f}};
  bool haveSide = !kClumps;
  for (std::uint32_t k = fp.hasGround ? 1u : 0u; k < v.numPlanes; ++k) {
    const Wall& w = v.planes[k];
    if (w.axis == kMeshWall) continue;  // its triangles below
    const std::size_t s = std::size_t(k) * v.numParticles + i;
    RevolvedPoint rp;
    const bool revolved = w.axis == kRevolvedWall;
    if (revolved) rp = revolvedContact(w, xi);
    // groundDepth(toWall(w, xi), …) > 0 for a plane; r − dist > 0 for a revolved wall; or a
    // JKR neck that holds
    if (r - (revolved ? rp.dist : wallHeight(w, xi) - w.coeffs.height) > 0.0f ||
        heldPlane<kLaw>(fp, v.ground.tx[s], v.ground.ty[s])) {
      if (!haveSide) {
        side = sideOf(self, v.own[i].u);
        haveSide = true;
      }
      float* tx = &v.ground.tx[s];
      float* ty = &v.ground.ty[s];
      GroundForces g;
      switch (w.axis) {
        case 0: g = planeContact<0, kClumps, kLaw>(v, fp, w, k, i, xi, toWall<0>(w, xi), r, self, side, tx, ty, out, work); break;
        case 1: g = planeContact<1, kClumps, kLaw>(v, fp, w, k, i, xi, toWall<1>(w, xi), r, self, side, tx, ty, out, work); break;
        case 2: g = planeContact<2, kClumps, kLaw>(v, fp, w, k, i, xi, toWall<2>(w, xi), r, self, side, tx, ty, out, work); break;
        case kGeneralPlane:
          g = planeContact<-1, kClumps, kLaw>(v, fp, w, k, i, xi, toWall<-1>(w, xi), r, self, side, tx, ty, out,
                                              work);
          break;
        default:  // the sphere at height dist above the surface's tangent plane
          g = planeContact<-1, kClumps, kLaw>(v, fp, rp.frame, k, i, xi, Vec3f{0.0f, 0.0f, rp.dist}, r, self, side, tx,
                                              ty, out, work);
          break;
      }
      gf->normal = anyPlane ? gf->normal + g.normal : g.normal;
      gf->friction = anyPlane ? gf->friction + g.friction : g.friction;
      anyPlane = true;
    } else {  // out of contact the stick spring is released
      v.ground.tx[s] = 0.0f;
      v.ground.ty[s] = 0.0f;
    }
  }
  if (v.mesh.numTriangles != 0)
    meshWallContacts<kClumps, kLaw, kPosedMesh>(v, fp, self, i, xi, r, side, haveSide, out, gf, anyPlane, work);
}

/// Particle i's side of its contacts (sideOf()), computed on first use: most particles touch
/// nothing. Single-sphere bodies (kClumps false) need only V, known from the start.
template <bool kClumps>
struct LazySide {
  ContactSide s;
  bool have;
  TUMBLE_HD_INLINE explicit LazySide(const BodyRow& self) : s{{0.0f, 0.0f, 0.0f}, self.v, {0.0f, 0.0f, 0.0f}}, have(!kClumps) {}
  TUMBLE_HD_INLINE const ContactSide& get(const StepView& v, const BodyRow& self, std::uint32_t i) {
    if (!have) {
      s = sideOf(self, v.own[i].u);
      have = true;
    }
    return s;
  }
};

/// What particleForce() sums for particle i: its force and torque and, for the debug capture
/// (kDebug), the three contact forces apart and its energy tally (EnergyWork). Trivial: start
/// from zeroSums().
template <bool kDebug>
struct ParticleSums {
  ParticleForce out;
  Vec3f rep, dmp, shr;
  EnergyWork work;
};
template <>
struct ParticleSums<false> {
  ParticleForce out;
};
template <bool kDebug>
TUMBLE_HD_INLINE ParticleSums<kDebug> zeroSums() {
  ParticleSums<kDebug> s;
  s.out = ParticleForce{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0u};
  if constexpr (kDebug) {
    s.rep = s.dmp = s.shr = Vec3f{0.0f, 0.0f, 0.0f};
    s.work = noWork();
  }
  return s;
}

/// The rolling resistance μ_r (0: none) of a contact with history cf between i (side si) and j
/// (sj) on i's body (out.t), and for the energy tally (kDebug) its torque and loss.
template <bool kDebug>
TUMBLE_HD_INLINE void addRolling(const ContactForces& cf, const ContactSide& si, const ContactSide& sj, float reff,
                                 float meff, float muR, float dt, ParticleForce& out, Vec3f& roll, float& loss) {
  if (!(muR > 0.0f)) return;
  const Vec3f m = rollingTorque(si.omega, sj.omega, cf.n, cf.normal, reff, meff, muR, dt);
  out.t += m;
  if constexpr (kDebug) {
    roll = m;
    loss = -dot(m, si.omega - sj.omega);
  }
}

/// The contact of particle i (at pi, of body `self`) with particle j of another body, entry e of
/// i's row, that touches: d = x_i − x_j and |d|² as the predicate computed them. Its force and
/// torque (and rolling torque) are added to *sum; a law with history updates its ξ (historyOf()).
/// Returns the force on i.
template <bool kDebug, bool kClumps, ContactLaw kLaw>
TUMBLE_HD_INLINE Vec3f addContact(const StepView& v, const ForceParams& fp, const BodyRow& self, std::uint32_t i,
                                 const PosRow& pi, std::uint32_t e, std::uint32_t j, Vec3f d, float d2,
                                 LazySide<kClumps>& side, ParticleSums<kDebug>* sum) {
  const float rj = v.pos[j].r;
  const BodyRow& other = v.bodies[kClumps ? v.bodyOf[j] : j];
  const ContactSide sj = kClumps ? sideOf(other, v.own[j].u) : ContactSide{Vec3f{0, 0, 0}, other.v, Vec3f{0, 0, 0}};
  const bool iBeforeJ = d2 > 0.0f || v.orig[i] < v.orig[j];  // read only for coincident centres
  ParticleForce& out = sum->out;
  ContactForces cf;
  [[maybe_unused]] Vec3f roll{0.0f, 0.0f, 0.0f};  // the tally's: the rolling torque M and its loss −M · (ω_i − ω_j)
  [[maybe_unused]] float rollingLoss = 0.0f;
  [[maybe_unused]] NeckFlow neck;  // the tally's (a JKR neck)
  // A cohesive contact's attraction (cohesion.hpp) at overlap delta, reff the pair's R*.
  const auto pull = [&](float value, float delta, float reff) {
    if (fp.cohesion == Cohesion::None) return Attraction{0.0f, 0.0f};
    return attraction(fp.cohesion, value, crossingRadius2(delta, pi.r, rj), reff);
  };
  if constexpr (kLaw == ContactLaw::HookeHistory) {
    const float meff = 1.0f / (self.invMass + other.invMass), reff = (pi.r * rj) / (pi.r + rj);
    const ContactSide& si = side.get(v, self, i);
    const ContactKinematics k = contactKinematics<kClumps>(d, d2, pi.r, rj, si, sj, iBeforeJ);
    cf = hookeHistoryForces(k, meff, fp.history, fp.dt, &historyOf(v, e), pull(fp.history.cohesion, k.delta, reff));
    addRolling<kDebug>(cf, si, sj, reff, meff, fp.rollingFriction, fp.dt, out, roll, rollingLoss);
  } else if constexpr (kLaw == ContactLaw::HertzMindlin) {
    const float meff = 1.0f / (self.invMass + other.invMass), reff = (pi.r * rj) / (pi.r + rj);
    const HertzPair& hp =
        v.hertz[materialPairIndex(materialOf(v.material, i), materialOf(v.material, j), v.numMaterials)];
    const ContactSide& si = side.get(v, self, i);
    const ContactKinematics k = contactKinematics<kClumps>(d, d2, pi.r, rj, si, sj, iBeforeJ);
    if (fp.cohesion == Cohesion::Jkr) {
      const JkrContact jc = jkrContact(k.delta, reff, hp.ystar, hp.cohesion);
      if (!jc.held) {  // a neck past its end (heldNeck()): released, no contact
        historyOf(v, e) = Vec3f{0.0f, 0.0f, 0.0f};
        return Vec3f{0.0f, 0.0f, 0.0f};
      }
      cf = jkrForces(k, meff, hp, fp.dt, &historyOf(v, e), jc, &neck);
    } else {
      cf = hertzMindlinForces(k, reff, meff, hp, fp.dt, &historyOf(v, e), pull(hp.cohesion, k.delta, reff));
    }
    addRolling<kDebug>(cf, si, sj, reff, meff, hp.muR, fp.dt, out, roll, rollingLoss);
  } else {
    cf = contactForces<kClumps>(d, d2, pi.r, rj, side.get(v, self, i), sj, iBeforeJ, fp.contact);
    if constexpr (kDebug) {  // the report's law is viscous: η |w|² and k_t |w_t|²
      const ContactKinematics k = contactKinematics<kClumps>(d, d2, pi.r, rj, side.get(v, self, i), sj, iBeforeJ);
      const float wn = dot(k.w, k.n);
      const Vec3f wt = k.w - wn * k.n;
      const Vec3f dn = dot(cf.damping, k.n) * k.n, drag = (cf.damping - dn) + cf.shear;
      const float t = dot(drag, wt);
      cf.loss = ContactLoss{dot(dn, k.n) * wn, t, t, dn, drag};
    }
  }
  const Vec3f fc = total(cf);
  out.f += fc;
  if (kClumps) out.t += cross(cf.arm, fc);
  if constexpr (kDebug) {
    sum->rep += cf.repulsion;
    sum->dmp += cf.damping;
    sum->shr += cf.shear;
    // Each pair is seen from both sides with the same losses: half from each.
    const Vec3f tangential = kLaw == ContactLaw::Report ? cf.loss.drag : cf.shear;  // the report's: all viscous
    addContactWork<kClumps>(sum->work, cf.loss, cf.loss.damping, cf.loss.drag, neck.power, neck.force, tangential,
                            cf.arm, roll, rollingLoss, 0.5f);
  }
  ++out.contacts;
  return fc;
}

/// After its contacts, the rest of particle i's step: its count of contacts (v.touching), the
/// planes (the ground first, then the walls; each plane's stick spring updated in place), the
/// pulls, and the debug capture (the capture's arrays where dbg has them; its energy tally
/// in sum.work). Returns its force and torque.
template <bool kDebug, bool kClumps, ContactLaw kLaw, bool kPosedMesh>
TUMBLE_HD_INLINE ParticleForce finishParticle(const StepView& v, const ForceParams& fp, const DebugForcesView& dbg,
                                              const BodyRow& self, std::uint32_t i, const PosRow& pi,
                                              LazySide<kClumps>& side, ParticleSums<kDebug>& sum) {
  ParticleForce& out = sum.out;
  const Vec3f xi{pi.x, pi.y, pi.z};
  v.touching[i] = static_cast<std::uint8_t>(out.contacts < 255u ? out.contacts : 255u);
  // The planes (wall.hpp), the ground first: its test reads the force constants (most particles
  // of a scene are above its ground), the walls' loop is wallContacts().
  GroundForces gf{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {}};  // debug: their sum
  EnergyWork* work = nullptr;
  if constexpr (kDebug) work = &sum.work;
  if (fp.hasGround) {
    // fp.ground = planes[0].coeffs; wallHeight() is z there
    if (groundDepth(xi, pi.r, fp.ground) > 0.0f || heldPlane<kLaw>(fp, v.ground.tx[i], v.ground.ty[i])) {
      gf = planeContact<kGroundFrame, kClumps, kLaw>(v, fp, v.planes[0], 0, i, xi, xi, pi.r, self, side.get(v, self, i),
                                                     &v.ground.tx[i], &v.ground.ty[i], &out, work);
    } else {  // out of contact the stick spring is released
      v.ground.tx[i] = 0.0f;
      v.ground.ty[i] = 0.0f;
    }
  }
  if (fp.hasWalls) {
    const bool groundTouched = fp.hasGround && (groundDepth(xi, pi.r, fp.ground) > 0.0f ||
                                                heldPlane<kLaw>(fp, v.ground.tx[i], v.ground.ty[i]));
    wallContacts<kClumps, kLaw, kPosedMesh>(v, fp, self, i, xi, pi.r, &out, &gf, groundTouched, work);
  }
  if (fp.pulls != 0u) {
    const Vec3f fpull = pullForce(xi, v.mass[i], fp.pullX, fp.pullY, fp.pullSwirl, fp.pulls, fp.pullCentre);
    out.f += fpull;
    if (kClumps) out.t += cross(side.get(v, self, i).offset, fpull);
  }
  if constexpr (kDebug) {
    const ContactSide& s = side.get(v, self, i);
    const Vec3f vel = kClumps ? pointVelocity(s.v, s.omega, s.offset) : s.v;
    const Vec3f parts[6] = {sum.rep, sum.dmp, sum.shr, gf.normal, gf.friction, vel};
    for (int k = 0; k < 6 && dbg.v != nullptr; ++k) {
      float* col = k < 5 ? dbg.f[k] : dbg.v;
      col[3 * std::size_t(i)] = parts[k].x;
      col[3 * std::size_t(i) + 1] = parts[k].y;
      col[3 * std::size_t(i) + 2] = parts[k].z;
    }
  }
  return out;
}

/// Whether the pair (i at pi, j at pj) touches: the shared predicate, through the minimum image
/// under kPeriodic; d and |d|² handed out.
template <bool kPeriodic>
TUMBLE_HD_INLINE bool touches(const StepView& v, const PosRow& pi, const PosRow& pj, Vec3f* d, float* d2) {
  if constexpr (kPeriodic)
    return spheresOverlap(v.periodic, pi.x, pi.y, pi.z, pi.r, pj.x, pj.y, pj.z, pj.r, &d->x, &d->y, &d->z, d2);
  else
    return spheresOverlap(pi.x, pi.y, pi.z, pi.r, pj.x, pj.y, pj.z, pj.r, &d->x, &d->y, &d->z, d2);
}

/// An open contact forgets its history: ξ of entry e of v.list zeroed (written only when it is
/// not zero already, isZeroSpring()).
TUMBLE_HD_INLINE void forgetHistory(const StepView& v, std::uint32_t e) {
  Vec3f& h = historyOf(v, e);
  if (!isZeroSpring(h)) h = Vec3f{0.0f, 0.0f, 0.0f};
}

/// Whether entry e, whose spheres do not overlap, is a JKR neck that may still hold (its spring
/// marked, heldSpring()): addContact() then decides, releasing it past the neck's end. Other
/// laws and models: never.
template <ContactLaw kLaw>
TUMBLE_HD_INLINE bool heldNeck(const StepView& v, const ForceParams& fp, std::uint32_t e) {
  if constexpr (kLaw == ContactLaw::HertzMindlin) return fp.cohesion == Cohesion::Jkr && !isZeroSpring(historyOf(v, e));
  return false;
}

/// Stages 3–5 for particle i of body `self` (SPEC §2.3–2.5): the contact list is the list of the
/// view (the candidate list, or on the CPU its near list) filtered by the exact predicate spheresOverlap() (the one the oracle uses), summed in
/// the list's order (ascending scene index of the partner; addContact()); then the planes in their order (the
/// ground, then the walls), then the pulls (finishParticle()). Each force adds arm × f to the torque about the body's
/// centre. Gravity is the body's (finishBody). Each pair is computed from both sides;
/// the contact laws are exactly antisymmetric, so the two sides agree to the bit.
///
/// kClumps: bodies rotate (some have several particles, or the law turns spheres). kLaw: the
/// contact law; with a history (hooke-history, hertz-mindlin) the view's `history` holds ξ per
/// candidate entry (historyOf()), updated in place and zeroed when the pair does not touch.
/// Under hertz-mindlin a plane is a Hertz contact too (hertzGroundForces).
/// kPeriodic: the pairs meet through their minimum image in the view's periodic box (the
/// predicate's periodic form, kernels/periodic.hpp); a scene without one pays nothing for it.
/// kPosedMesh: some mesh wall moves (meshWallContacts()); a scene whose meshes stand still (or
/// that has none) runs the code without poses.
///
/// kDebug: *work (nullptr: none) gains the particle's energy tally (EnergyWork).
template <bool kDebug, bool kClumps, ContactLaw kLaw = ContactLaw::Report, bool kPeriodic = false,
          bool kPosedMesh = false>
TUMBLE_HD_INLINE ParticleForce particleForce(const StepView& v, const ForceParams& fp, const DebugForcesView& dbg,
                                             const BodyRow& self, std::uint32_t i, EnergyWork* work = nullptr) {
  const PosRow pi = v.pos[i];
  LazySide<kClumps> side(self);
  ParticleSums<kDebug> sum = zeroSums<kDebug>();
  const std::uint32_t end = v.list.end[i];
  for (std::uint32_t e = v.list.begin[i]; e < end; ++e) {
    const std::uint32_t j = v.list.cand[e];
    Vec3f d;
    float d2;
    if (!touches<kPeriodic>(v, pi, v.pos[j], &d, &d2) && !heldNeck<kLaw>(v, fp, e)) {
      if constexpr (kLaw != ContactLaw::Report) forgetHistory(v, e);
      if constexpr (kDebug) {
        if (dbg.contact != nullptr) dbg.contact[e].i = kNoContact;
      }
      continue;
    }
    const std::uint32_t before = sum.out.contacts;
    const Vec3f f = addContact<kDebug, kClumps, kLaw>(v, fp, self, i, pi, e, j, d, d2, side, &sum);
    if constexpr (kDebug) {  // (a JKR neck released: no contact)
      if (dbg.contact != nullptr) {
        if (sum.out.contacts != before) dbg.contact[e] = capturedContact(v, i, pi, j, d, d2, f);
        else dbg.contact[e].i = kNoContact;
      }
    }
  }
  const ParticleForce pf = finishParticle<kDebug, kClumps, kLaw, kPosedMesh>(v, fp, dbg, self, i, pi, side, sum);
  if constexpr (kDebug) {
    if (work != nullptr) addWork(*work, sum.work);
  }
  return pf;
}

/// Stage 6, one particle's share of its body's totals: F += f_i, T += t_i. A body adds its
/// particles in their order within the body.
template <bool kClumps>
TUMBLE_HD_INLINE void addToBody(Vec3f& F, Vec3f& T, const ParticleForce& pf) {
  F += pf.f;
  if (kClumps) T += pf.t;
}

/// particleForce() for the particles of body `self` at once (the CPU's pass, any law, a compact
/// list with its owners, StepView::listOwner): the body's rows, one run of entries,
/// are first filtered into a buffer of the touching entries with no branch per entry, then the
/// contacts are summed particle by particle in row order (addContact()) and each particle
/// finished in order (finishParticle()): particleForce()'s operations in its order, so the same
/// bits, with about one mispredicted branch per body instead of one or two per particle (the
/// candidate loop's exit and its touch test, which goes either way about as often). A body with
/// more than kBodyBatchParticles particles or kBodyBatch entries, or a list without owners, goes
/// particle by particle. Adds each particle's force to F and T (addToBody()) and returns the
/// number of contacts. A law with history: the filter zeroes the ξ of the entries that do not
/// touch (forgetHistory()), the contacts update theirs; each entry has its own ξ, so the order
/// of the two does not matter and the histories are particleForce()'s too. kDebug (the energy
/// tally without the capture, whose arrays dbg must not have): *work gains the particles'
/// EnergyWork, in particleForce()'s order too.
inline constexpr std::uint32_t kBodyBatch = 96, kBodyBatchParticles = 16;
template <bool kClumps, ContactLaw kLaw, bool kPeriodic, bool kPosedMesh, bool kDebug = false>
TUMBLE_HD_INLINE std::uint32_t bodyForces(const StepView& v, const ForceParams& fp, const DebugForcesView& dbg,
                                          const BodyRow& self, Vec3f* F, Vec3f* T, EnergyWork* work = nullptr) {
  const std::uint32_t first = self.first, count = self.count;
  // A compact list: the body's rows are one run of entries. (Its ends are read again for the
  // loop below: kept live across the branch, they cost 5 % of the pass at 16k, measured.)
  const std::uint32_t entries = v.list.end[first + count - 1] - v.list.begin[first];
  std::uint32_t contacts = 0;
  if (v.listOwner == nullptr || count > kBodyBatchParticles || entries > kBodyBatch) {
    for (std::uint32_t i = first; i < first + count; ++i) {
      const ParticleForce pf = particleForce<kDebug, kClumps, kLaw, kPeriodic, kPosedMesh>(v, fp, dbg, self, i, work);
      addToBody<kClumps>(*F, *T, pf);
      contacts += pf.contacts;
    }
    return contacts;
  }
  // The touching entries of the body's rows, in row order: (particle within the body, entry).
  struct Hit {
    Vec3f d;
    float d2;
    std::uint32_t e;
    std::uint32_t k;
  };
  Hit hits[kBodyBatch];
  std::uint32_t numHits = 0;
  for (std::uint32_t e = v.list.begin[first], end = v.list.end[first + count - 1]; e < end; ++e) {
    const std::uint32_t i = v.listOwner[e];
    Hit& h = hits[numHits];
    h.e = e;
    h.k = i - first;
    const bool hit = touches<kPeriodic>(v, v.pos[i], v.pos[v.list.cand[e]], &h.d, &h.d2) || heldNeck<kLaw>(v, fp, e);
    if constexpr (kLaw != ContactLaw::Report) {
      if (!hit) forgetHistory(v, e);
    }
    numHits += hit ? 1u : 0u;
  }
  ParticleSums<kDebug> sums[kBodyBatchParticles];
  for (std::uint32_t k = 0; k < count; ++k) sums[k] = zeroSums<kDebug>();
  for (std::uint32_t h = 0; h < numHits; ++h) {
    const Hit& x = hits[h];
    const std::uint32_t i = first + x.k;
    LazySide<kClumps> side(self);  // (per contact: cheaper than keeping one per particle)
    addContact<kDebug, kClumps, kLaw>(v, fp, self, i, v.pos[i], x.e, v.list.cand[x.e], x.d, x.d2, side, &sums[x.k]);
  }
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint32_t i = first + k;
    LazySide<kClumps> side(self);
    const ParticleForce pf =
        finishParticle<kDebug, kClumps, kLaw, kPosedMesh>(v, fp, dbg, self, i, v.pos[i], side, sums[k]);
    if constexpr (kDebug) {
      if (work != nullptr) addWork(*work, sums[k].work);
    }
    addToBody<kClumps>(*F, *T, pf);
    contacts += pf.contacts;
  }
  return contacts;
}

/// A bound on the displacement of every particle of body b since its reference `ref` (the skin
/// test per body, StepView::bodyRef), added to *drift as a box about the centre's displacement
/// ΔX: |Δx_i| ≤ |ΔX| + e with e = 2 |q − q_ref| reach + the rounding of the positions, since
/// |R(q) u − R(q_ref) u| ≤ 2 |q − q_ref| |u| for unit quaternions (q u q* − q' u q'* = (q − q') u q*
/// + q' u (q − q')*), and the float positions X + R u of the two states carry at most
/// 2^-24 (|X| + |X_ref|) + 32 · 2^-24 reach of rounding between them (the matrix from a float q,
/// the product, the sum); e is taken 4 times that and rounded up. Every particle's displacement
/// vector lies in ΔX ± e per axis, so the box and the largest |Δx| hold them: the list stays
/// valid (closureOf()), as with the displacements measured particle by particle. kPeriodic: ΔX
/// through the minimum image, so that a wrap does not count as motion.
template <bool kPeriodic>
TUMBLE_HD_INLINE void bodyDrift(const StepView& v, const BodyRow& b, float reach, const BodyRef& ref, Drift* drift) {
  const Vec3f dX = kPeriodic ? periodicDifference(v.periodic, b.x, ref.x) : b.x - ref.x;
  const float qx = b.q.x - ref.q.x, qy = b.q.y - ref.q.y, qz = b.q.z - ref.q.z, qw = b.q.w - ref.q.w;
  const float dq = sqrtf(qw * qw + qx * qx + qy * qy + qz * qz);
  const float size = fabsf(b.x.x) + fabsf(b.x.y) + fabsf(b.x.z) + fabsf(ref.x.x) + fabsf(ref.x.y) + fabsf(ref.x.z);
  const float e = (2.0f * dq * reach + 0x1p-22f * size + 0x1p-17f * reach) * (1.0f + 0x1p-20f);
  addBodyDisplacement(*drift, dX.x, dX.y, dX.z, e);
}

/// Stage 7 and the next step's stage 1 for body k, given the sums F and T of its particles
/// (addToBody): adds the weight M g, integrates (rotation by `scheme`, only for bodies of more
/// than one particle; Ω and R of the new state kept in the row), writes its particles' positions
/// of the next state and adds their displacements since buildPos to *drift. kPeriodic: a centre
/// that left the view's periodic box is moved back by a period and the crossing counted
/// (wrapIntoBox()), before the particles' positions are taken from it.
template <bool kClumps, bool kPeriodic = false>
TUMBLE_HD_INLINE void finishBody(const StepView& v, Vec3f F, Vec3f T, Vec3f gravity, float dt, RotationScheme scheme,
                                 std::uint32_t k, Drift* drift) {
  BodyRow b = v.bodies[k];  // this step's row; the new state goes to bodiesNext
  const BodyStatic bs = v.bodyStatic[k];
  F += bs.mass * gravity;
  integrateTranslation(F, b.invMass, dt, &b.x, &b.v);
  if constexpr (kPeriodic) wrapIntoBox(v.periodic, &b.x, b.image);
  if (kClumps && (b.count > 1 || v.rotateSpheres))  // else a single sphere that does not rotate: q and R stay
    b.omega = scheme == RotationScheme::Splitting ? integrateRotationSplitting(T, bs.invInertia, dt, &b.l, &b.q, &b.rot)
                                                  : integrateRotation(T, bs.invInertia, dt, &b.l, &b.q, &b.rot);
  v.bodiesNext[k] = b;
  if (kClumps && v.bodyRef != nullptr) {  // the skin test per body: its particles' positions only
    bodyDrift<kPeriodic>(v, b, bs.reach, v.bodyRef[k], drift);
    bodyParticles<kClumps, kPeriodic>(b, v.own, v.radius, nullptr, v.posNext, drift, v.periodic);
  } else {
    bodyParticles<kClumps, kPeriodic>(b, v.own, v.radius, v.buildPos, v.posNext, drift, v.periodic);
  }
}

/// Stages 3–7 and the next step's stage 1 for body k, in one pass (both pipelines' step, one
/// writer per body): its particles' forces in order (particleForce(); with kBodyBatch, without
/// the debug capture's arrays, the body batch, bodyForces(), which gives the same bits),
/// summed into its force and torque as they come (addToBody()), then finishBody(). The body's
/// force and torque never leave the registers: no per-particle force is stored for a second
/// pass. Returns the contacts its particles counted. kBodyBatch: the CPU pipeline, whose lists
/// have owners; the CUDA pipeline's have none, and the batch's buffers (about 3 KB a thread)
/// would be reserved for nothing. kDebug with v.bodyFlows: the body's energy flows, its
/// particles' in order, moved to the middle of the step (EnergyWork), go to v.bodyFlows[k]
/// (the energy tally, kernels/energy.hpp).
template <bool kDebug, bool kClumps, ContactLaw kLaw, bool kPeriodic, bool kPosedMesh, bool kBodyBatch>
TUMBLE_HD_INLINE std::uint32_t stepBody(const StepView& v, const ForceParams& fp, const DebugForcesView& dbg,
                                        Vec3f gravity, float dt, RotationScheme scheme, std::uint32_t k, Drift* drift) {
  const BodyRow& self = v.bodies[k];
  Vec3f F{0.0f, 0.0f, 0.0f}, T{0.0f, 0.0f, 0.0f};
  std::uint32_t contacts = 0;
  [[maybe_unused]] EnergyWork work = noWork();
  bool batched = false;
  if constexpr (kBodyBatch) {  // also for the energy tally alone (kDebug without the capture's arrays)
    if (!kDebug || (dbg.v == nullptr && dbg.contact == nullptr)) {
      contacts = bodyForces<kClumps, kLaw, kPeriodic, kPosedMesh, kDebug>(v, fp, dbg, self, &F, &T, &work);
      batched = true;
    }
  }
  if (!batched) {
    for (std::uint32_t i = self.first, e = self.first + self.count; i < e; ++i) {
      const ParticleForce pf = particleForce<kDebug, kClumps, kLaw, kPeriodic, kPosedMesh>(v, fp, dbg, self, i, &work);
      addToBody<kClumps>(F, T, pf);
      contacts += pf.contacts;
    }
  }
  finishBody<kClumps, kPeriodic>(v, F, T, gravity, dt, scheme, k, drift);
  if constexpr (kDebug) {
    if (v.bodyFlows != nullptr) {  // finishBody() wrote the next row; self is this step's
      const BodyRow& next = v.bodiesNext[k];
      const Vec3f dV = next.v - self.v, dW = next.omega - self.omega;
      float* flow[4] = {&work.flows.normal, &work.flows.tangential, &work.flows.friction, &work.flows.cohesion};
      for (int c = 0; c < 4; ++c) *flow[c] -= 0.5f * (dot(work.f[c], dV) + dot(work.t[c], dW));
      v.bodyFlows[k] = work.flows;
    }
  }
  return contacts;
}

}  // namespace tumble
