// SPDX-License-Identifier: MIT
// The CUDA pipeline's functors of a step and of a batch of steps (pipeline.hpp): stage 1's
// particle positions (StateFn), the per-body pass of stages 3–7 (StepBodyFn), what each step
// reads back (StepReadback: the drift and the contacts, merged by integer atomics), and the skin
// test on the device after each step of a batch (DecideFn), or again per particle after
// writeMotion() (ParticleDriftFn). Each a call of a shared function of core/ (kernels/step.hpp,
// kernels/contact_list.hpp). Internal to tumble::gpu.
#pragma once
#include <cstdint>

#include "exec/exec.hpp"
#include "tumble/kernels/cell_key.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/step.hpp"
#include "tumble/scene.hpp"

namespace tumble::gpu::detail {
inline namespace TUMBLE_EXEC_ABI {  // one copy per compiler (exec.hpp)

// Stage 1 at a rebuild: particle positions from the bodies.
template <bool kClumps>
struct StateFn {
  const BodyRow* bodies;
  const OwnRow* own;
  const float* radius;
  PosRow* pos;
  TUMBLE_HD void operator()(std::uint32_t k) const {
    bodyParticles<kClumps>(bodies[k], own, radius, nullptr, pos, nullptr);
  }
};

/// What each step reads back: the drift (skin test; as order-preserving integer images of the
/// floats, so that integer atomics give the exact max and min in any order) and the contacts.
struct StepReadback {
  unsigned int max2, lo[3], hi[3];
  unsigned int pad;
  unsigned long long contacts;
};

// A drift merged into the read-back by integer atomics on the floats' ordered images: exact in
// any order.
TUMBLE_HD_INLINE void mergeDriftInto(StepReadback* rb, const Drift& d) {
  exec::atomicMaxU32(&rb->max2, orderedBits(d.max2));
  for (int a = 0; a < 3; ++a) {
    exec::atomicMinU32(&rb->lo[a], orderedBits(d.lo[a]));
    exec::atomicMaxU32(&rb->hi[a], orderedBits(d.hi[a]));
  }
}

// The skin test again per particle (HaloPipeline::writeMotion): its displacement since the
// rebuild, through the minimum image on periodic axes (as the step's, kernels/step.hpp).
struct ParticleDriftFn {
  const PosRow* pos;
  const PosRow* buildPos;
  PeriodicBox box;
  StepReadback* rb;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    Drift d = noDrift();
    if (box.axes != 0)
      addParticleDisplacement<true>(d, pos[i], buildPos[i], box);
    else
      addParticleDisplacement<false>(d, pos[i], buildPos[i], box);
    mergeDriftInto(rb, d);
  }
};

// Stages 3–7 and the next step's stage 1 per body (stepBody(): its particles' forces summed in
// order as they come, then its integration); the drift's max and mins and the contacts by
// integer atomics.
template <bool kDebug, bool kClumps, ContactLaw kLaw, bool kPeriodic, bool kPosedMesh>
struct StepBodyFn {
  StepView v;
  ForceParams fp;
  DebugForcesView dbg;
  Vec3f gravity;
  float dt;
  RotationScheme scheme;
  StepReadback* rb;
  const std::uint32_t* stop;  // non-zero: an earlier step of the batch asked for a rebuild (DecideFn)
  TUMBLE_HD void operator()(std::uint32_t k) const {
    if (*stop != 0) return;
    Drift d = noDrift();
    const std::uint32_t contacts =
        stepBody<kDebug, kClumps, kLaw, kPeriodic, kPosedMesh, false>(v, fp, dbg, gravity, dt, scheme, k, &d);
    mergeDriftInto(rb, d);
    if (contacts != 0) exec::atomicAddU64(&rb->contacts, static_cast<unsigned long long>(contacts));  // exact
  }
};

// The energy tally of one step of a batch (kernels/energy.hpp): the flows of the step's bodies
// (StepView::bodyFlows), kTallyRun of them per element summed in its limbs, then added to *out's
// by integer atomics (exact in any order; a run, not a body, per atomic: fewer on the same 12
// words); nothing for a step the batch did not take (*stop, as StepBodyFn).
inline constexpr std::uint32_t kTallyRun = 64;
struct TallyFn {
  const EnergyFlows* flows;
  std::uint32_t numBodies;
  float dt;
  const std::uint32_t* stop;
  EnergyLimbs* out;
  TUMBLE_HD void operator()(std::uint32_t run) const {
    if (*stop != 0) return;
    EnergyLimbs l = noLimbs();
    for (std::uint32_t k = run * kTallyRun, e = k + kTallyRun < numBodies ? k + kTallyRun : numBodies; k < e; ++k)
      addEnergy(l, flows[k], dt);
    for (int c = 0; c < kEnergyFlows; ++c) {
      if (l.hi[c] != 0) exec::atomicAddU64(&out->hi[c], l.hi[c]);
      if (l.mid[c] != 0) exec::atomicAddU64(&out->mid[c], l.mid[c]);
      if (l.lo[c] != 0) exec::atomicAddU64(&out->lo[c], l.lo[c]);
    }
  }
};

// The drift a read-back holds.
TUMBLE_HD_INLINE Drift driftOf(const StepReadback& h) {
  Drift drift{fromOrderedBits(h.max2), {}, {}};
  for (int a = 0; a < 3; ++a) {
    drift.lo[a] = fromOrderedBits(h.lo[a]);
    drift.hi[a] = fromOrderedBits(h.hi[a]);
  }
  return drift;
}

// The skin test (as CpuPipeline::decideList, without a near list): whether the list must be
// rebuilt after a step whose particles drifted by d since the rebuild; walls: there are mesh
// walls (the closure on a static wall too, wallClosureOf()); meshes: the moving meshes' closure
// since the rebuild up to the next step's start.
TUMBLE_HD_INLINE bool rebuildDue(const Drift& d, bool walls, double meshes, float limit) {
  const float closure = walls ? wallClosureOf(d) : closureOf(d);
  return !(double(closure) + meshes < double(limit));
}

// After step s of a batch (one element): rebuildDue() on the device. Where the list is no
// longer valid, *stop = s + 1: the batch's later steps do nothing and the host rebuilds before
// the next.
struct DecideFn {
  const StepReadback* rb;
  const double* meshes;  // per step of the batch, the moving meshes' closure since the rebuild
  std::uint32_t s;
  float limit;
  bool walls;  // mesh walls: the closure on a static wall too (wallClosureOf())
  std::uint32_t* stop;
  TUMBLE_HD void operator()(std::uint32_t) const {
    if (*stop == 0 && rebuildDue(driftOf(rb[s]), walls, meshes[s], limit)) *stop = s + 1;
  }
};

}  // namespace TUMBLE_EXEC_ABI
}  // namespace tumble::gpu::detail
