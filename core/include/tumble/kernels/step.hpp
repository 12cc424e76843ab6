// SPDX-License-Identifier: MIT
/// @file step.hpp
/// The per-element bodies of the step's stages (SPEC §2), written once for both pipelines:
/// the CPU calls them from TBB loops, the CUDA pipeline from two-line __global__ wrappers.
/// Each function writes only element i's (or body k's) outputs and sums in a fixed order, so
/// the results do not depend on the scheduling.
#pragma once
#include <cstddef>
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/kernels/contact.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/math.hpp"
#include "tumble/scene.hpp"
#include "tumble/soa.hpp"

namespace tumble {

/// The CSR contact list of the broadphase: particle i's records recFirst[i]..recFirst[i+1]
/// (sorted position inv[r]) list forward neighbours nbr[nbrOffsets[s]..nbrOffsets[s+1]); the
/// backward neighbours are back[backOffsets[i]..backOffsets[i+1]].
struct ContactListView {
  const std::uint32_t* recFirst;
  const std::uint32_t* inv;
  const std::uint32_t* nbrOffsets;
  const std::uint32_t* nbr;
  const std::uint32_t* backOffsets;
  const std::uint32_t* back;
};

/// Clump data of the force stage (clump scenes only): per-particle couples of the forces
/// acting at contact points (out), and each body's angular velocity Ω (in), for the velocities
/// at the contact points.
struct CouplesView {
  float* x;
  float* y;
  float* z;
  const Vec3f* omega;
};

/// Scene constants of the force stage.
struct ForceParams {
  ContactCoeffs contact;
  GroundCoeffs ground;
  Vec3f gravity;
  float pullX, pullY, pullSwirl;
  Vec3f pullCentre;
  float dt;
  std::uint32_t pulls;
  bool hasGround;
};

/// The force-stage constants of a scene with the given pulls on (host side).
inline ForceParams makeForceParams(const Scene& p, std::uint32_t pulls) {
  const float kt = p.ground.tangentialStiffness > 0.0f ? p.ground.tangentialStiffness : p.ground.stiffness * (2.0f / 7.0f);
  return ForceParams{ContactCoeffs{p.contact.stiffness, p.contact.damping, p.contact.shear},
                     GroundCoeffs{p.ground.height, p.ground.stiffness, kt, p.ground.friction},
                     p.gravity,
                     p.pulls.x,
                     p.pulls.y,
                     p.pulls.swirl,
                     p.pulls.centre,
                     p.dt,
                     pulls,
                     p.ground.enabled};
}

/// Debug capture: repulsion, damping, shear, ground, friction; 3 floats per particle each.
struct DebugForcesView {
  float* f[5];
};

/// Stage 1: particle i's x, v and R u from its body (clump scenes only).
TUMBLE_HD_INLINE void particleStateOf(const BodiesView& b, const Vec3f* omega, const ParticleStaticView& st,
                                      const ParticleStateView& ps, std::uint32_t i) {
  const std::uint32_t k = st.body[i];
  Vec3f xo, vo;
  const Vec3f ru = particleFromBody(Vec3f{b.px[k], b.py[k], b.pz[k]}, Vec3f{b.vx[k], b.vy[k], b.vz[k]},
                                    Quatf{b.qw[k], b.qx[k], b.qy[k], b.qz[k]}, omega[k],
                                    Vec3f{st.ux[i], st.uy[i], st.uz[i]}, &xo, &vo);
  ps.x[i] = xo.x; ps.y[i] = xo.y; ps.z[i] = xo.z;
  ps.vx[i] = vo.x; ps.vy[i] = vo.y; ps.vz[i] = vo.z;
  ps.rx[i] = ru.x; ps.ry[i] = ru.y; ps.rz[i] = ru.z;
}

namespace detail {

/// Running sums of one particle's force stage.
struct ForceSums {
  Vec3f f{0.0f, 0.0f, 0.0f}, tau{0.0f, 0.0f, 0.0f};
  Vec3f rep{0.0f, 0.0f, 0.0f}, dmp{0.0f, 0.0f, 0.0f}, shr{0.0f, 0.0f, 0.0f};
};

template <bool kDebug, bool kClumps>
TUMBLE_HD_INLINE void addContact(ForceSums& s, std::uint32_t i, Vec3f xi, Vec3f vi, Vec3f wi, float ri, std::uint32_t j,
                                 const ParticleStaticView& st, const ParticleStateView& ps, const CouplesView& couples,
                                 const ForceParams& fp) {
  const Vec3f wj = kClumps ? couples.omega[st.body[j]] : Vec3f{0.0f, 0.0f, 0.0f};
  const ContactForces cf = contactForces(xi, vi, wi, ri, Vec3f{ps.x[j], ps.y[j], ps.z[j]},
                                         Vec3f{ps.vx[j], ps.vy[j], ps.vz[j]}, wj, st.radius[j], i < j, fp.contact);
  const Vec3f fc = total(cf);
  s.f += fc;
  if (kClumps) s.tau += cross(cf.lever, fc);
  if (kDebug) {
    s.rep += cf.repulsion;
    s.dmp += cf.damping;
    s.shr += cf.shear;
  }
}

}  // namespace detail

/// Stages 3–5: particle i's total force (and couple), in a fixed order: forward neighbours by
/// record, then backward neighbours, then the ground (its stick spring ps.tx/ty updated),
/// then gravity and pulls.
template <bool kDebug, bool kClumps>
TUMBLE_HD_INLINE void particleForces(const ParticleStaticView& st, const ParticleStateView& ps,
                                     const CouplesView& couples, const ContactListView& cl, const ForceParams& fp,
                                     const DebugForcesView& dbg, std::uint32_t i) {
  const Vec3f xi{ps.x[i], ps.y[i], ps.z[i]};
  const Vec3f vi{ps.vx[i], ps.vy[i], ps.vz[i]};
  const float ri = st.radius[i];
  const Vec3f wi = kClumps ? couples.omega[st.body[i]] : Vec3f{0.0f, 0.0f, 0.0f};
  detail::ForceSums s;
  for (std::uint32_t r = cl.recFirst[i]; r < cl.recFirst[i + 1]; ++r) {
    const std::uint32_t sp = cl.inv[r];
    for (std::uint32_t e = cl.nbrOffsets[sp]; e < cl.nbrOffsets[sp + 1]; ++e)
      detail::addContact<kDebug, kClumps>(s, i, xi, vi, wi, ri, cl.nbr[e], st, ps, couples, fp);
  }
  for (std::uint32_t e = cl.backOffsets[i]; e < cl.backOffsets[i + 1]; ++e)
    detail::addContact<kDebug, kClumps>(s, i, xi, vi, wi, ri, cl.back[e], st, ps, couples, fp);
  GroundForces gf{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}};
  if (fp.hasGround) {
    float tx = ps.tx[i], ty = ps.ty[i];
    gf = groundForces(xi, vi, wi, ri, st.groundDamping[i], fp.ground, fp.dt, &tx, &ty);
    ps.tx[i] = tx;
    ps.ty[i] = ty;
    s.f += gf.normal + gf.friction;
    if (kClumps) s.tau += cross(gf.lever, gf.friction);  // friction acts at the bottom
  }
  s.f += externalForce(xi, st.mass[i], fp.gravity, fp.pullX, fp.pullY, fp.pullSwirl, fp.pulls, fp.pullCentre);
  ps.fx[i] = s.f.x;
  ps.fy[i] = s.f.y;
  ps.fz[i] = s.f.z;
  if (kClumps) {
    couples.x[i] = s.tau.x;
    couples.y[i] = s.tau.y;
    couples.z[i] = s.tau.z;
  }
  if (kDebug) {
    const Vec3f parts[5] = {s.rep, s.dmp, s.shr, gf.normal, gf.friction};
    for (int k = 0; k < 5; ++k) {
      dbg.f[k][3 * std::size_t(i)] = parts[k].x;
      dbg.f[k][3 * std::size_t(i) + 1] = parts[k].y;
      dbg.f[k][3 * std::size_t(i) + 2] = parts[k].z;
    }
  }
}

/// Stages 6–7: body k's totals F = Σ f_i, T = Σ R u_i × f_i + Σ τ_i (particle order), then the
/// integration (rotation by `scheme`); omega[k] receives Ω of the new state.
TUMBLE_HD_INLINE void integrateBody(const BodiesView& b, const ParticleStateView& ps, const CouplesView& couples,
                                    Vec3f* omega, float dt, bool clumps, RotationScheme scheme, std::uint32_t k) {
  Vec3f F, T{0.0f, 0.0f, 0.0f};
  if (clumps) {
    F = Vec3f{0.0f, 0.0f, 0.0f};
    const std::uint32_t a = b.first[k], e = a + b.numParticles[k];
    for (std::uint32_t i = a; i < e; ++i) {
      const Vec3f fi{ps.fx[i], ps.fy[i], ps.fz[i]};
      F += fi;
      T += cross(Vec3f{ps.rx[i], ps.ry[i], ps.rz[i]}, fi) + Vec3f{couples.x[i], couples.y[i], couples.z[i]};
    }
  } else {
    F = Vec3f{ps.fx[k], ps.fy[k], ps.fz[k]};
  }
  Vec3f X{b.px[k], b.py[k], b.pz[k]}, V{b.vx[k], b.vy[k], b.vz[k]};
  integrateTranslation(F, b.invMass[k], dt, &X, &V);
  b.px[k] = X.x; b.py[k] = X.y; b.pz[k] = X.z;
  b.vx[k] = V.x; b.vy[k] = V.y; b.vz[k] = V.z;
  if (clumps && b.numParticles[k] > 1) {
    Vec3f L{b.lx[k], b.ly[k], b.lz[k]};
    Quatf q{b.qw[k], b.qx[k], b.qy[k], b.qz[k]};
    omega[k] = scheme == RotationScheme::Splitting ? integrateRotationSplitting(T, b.invInertia[k], dt, &L, &q)
                                                   : integrateRotation(T, b.invInertia[k], dt, &L, &q);
    b.lx[k] = L.x; b.ly[k] = L.y; b.lz[k] = L.z;
    b.qw[k] = q.w; b.qx[k] = q.x; b.qy[k] = q.y; b.qz[k] = q.z;
  }
}

}  // namespace tumble
