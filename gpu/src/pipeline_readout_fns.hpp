// SPDX-License-Identifier: MIT
// The CUDA pipeline's functors of its read-outs (pipeline_readout.hpp): the hooks of a domain
// decomposition (HaloPipeline), the guard's contact sums per body, and the last step's contacts
// with particles and with mesh triangles, each written at its scene index's offset so that the
// output comes out sorted. Internal to tumble::gpu.
#pragma once
#include <cstdint>

#include "exec/exec.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/contact_sums.hpp"
#include "tumble/kernels/mesh.hpp"
#include "tumble/kernels/step.hpp"
#include "tumble/soa.hpp"
#include "tumble/world.hpp"

namespace tumble::gpu::detail {
inline namespace TUMBLE_EXEC_ABI {  // one copy per compiler (exec.hpp)

// The hooks of a domain decomposition (HaloPipeline): the internal index of each body by scene
// index, and the rows of the listed bodies read, overwritten (their particles' positions
// recomputed) and their contacts counted.
struct BodyIndexFn {
  const BodyRow* bodies;
  std::uint32_t* at;
  TUMBLE_HD void operator()(std::uint32_t k) const { at[bodies[k].orig] = k; }
};

struct ReadMotionFn {
  const BodyRow* bodies;
  const std::uint32_t* at;
  const std::uint32_t* list;
  BodyMotion* out;
  TUMBLE_HD void operator()(std::uint32_t k) const { out[k] = motionOf(bodies[at[list[k]]]); }
};

template <bool kClumps>
struct WriteMotionFn {
  BodyRow* bodies;
  const std::uint32_t* at;
  const std::uint32_t* list;
  const BodyMotion* motion;
  const OwnRow* own;
  const float* radius;
  PosRow* pos;
  TUMBLE_HD void operator()(std::uint32_t k) const {
    BodyRow& b = bodies[at[list[k]]];
    setMotion(b, motion[k]);
    bodyParticles<kClumps>(b, own, radius, nullptr, pos, nullptr);
  }
};

struct BodyContactCountFn {
  const BodyRow* bodies;
  const std::uint32_t* at;
  const std::uint32_t* list;
  const std::uint8_t* touching;
  const PosRow* pos;
  CandidateListView l;
  PeriodicBox box;
  unsigned long long* total;
  TUMBLE_HD void operator()(std::uint32_t k) const {
    const std::uint64_t c = bodyContactCount(bodies[at[list[k]]], touching, pos, l, box);
    if (c != 0) exec::atomicAddU64(total, static_cast<unsigned long long>(c));  // exact
  }
};

// contactSumsPerBody(): one body's sums (bodyContactSums()), written at its scene index.
struct BodyContactSumsFn {
  const BodyRow* bodies;
  const std::uint32_t* bodyOf;
  const std::uint8_t* touching;
  const PosRow* was;
  const PosRow* now;
  const std::uint32_t* orig;
  CandidateListView list;
  SpringLaw law;
  PeriodicBox box;
  ContactSums* out;
  TUMBLE_HD void operator()(std::uint32_t b) const {
    out[bodies[b].orig] = bodyContactSums(bodies, bodyOf, touching, was, now, orig, list, law, box, b);
  }
};

// meshContacts(): per particle the triangles its sphere meets (forMeshHits()), written at its
// scene index's offset, so that the output comes out sorted by (particle, triangle).
struct MeshHitsVisit {
  MeshView mesh;
  const std::uint32_t* offsets;
  const std::uint32_t* tri;
  const PosRow* pos;
  const std::uint32_t* orig;
  TUMBLE_HD std::uint32_t slot(std::uint32_t i) const { return orig[i]; }
  template <class F>
  TUMBLE_HD void operator()(std::uint32_t i, F&& f) const {
    forMeshHits(mesh, offsets, tri, pos[i], i, f);
  }
};

struct MeshHitsFillFn {
  MeshHitsVisit visit;
  const std::uint32_t* at;
  MeshContact* out;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    std::uint32_t k = at[visit.slot(i)];
    visit(i, [&](std::uint32_t t) { out[k++] = MeshContact{visit.orig[i], t}; });
  }
};

// pairs(): per particle the contacts with a higher scene index, written at its scene index's
// offset, so that the output comes out sorted by (i, j); with periodic boundaries through the
// minimum image. touching: the particles to walk (the force stage's; nullptr: all). Element n
// writes the trailing zero.
struct ContactsAboveFn {
  const PosRow* pos;
  const std::uint32_t* orig;
  CandidateListView list;
  const std::uint8_t* touching;
  PeriodicBox box;
  std::uint32_t n;
  std::uint32_t* countByOrig;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    if (i == n) countByOrig[n] = 0;
    else countByOrig[orig[i]] = touching == nullptr || touching[i] ? contactsAbove(pos, orig, list, i, box) : 0u;
  }
};

struct EmitContactsFn {
  const PosRow* pos;
  const std::uint32_t* orig;
  CandidateListView list;
  const std::uint8_t* touching;
  PeriodicBox box;
  const std::uint32_t* at;
  std::uint32_t* outI;
  std::uint32_t* outJ;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    if (touching == nullptr || touching[i]) emitContactsAbove(pos, orig, list, i, at[orig[i]], outI, outJ, box);
  }
};

}  // namespace TUMBLE_EXEC_ABI
}  // namespace tumble::gpu::detail
