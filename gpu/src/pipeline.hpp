// SPDX-License-Identifier: MIT
// The CUDA pipeline (SPEC §2–§4), written once over the execution layer (exec/exec.hpp) and
// compiled twice: by nvcc for the device (CudaExec: cuda_pipeline.cu, Backend::Cuda) and by g++
// for the host backend (HostExec: host_pipeline.cpp, Backend::CudaHost). The CPU pipeline's
// stages (cpu/src/cpu_pipeline.cpp), one kernel per stage.
//
// Design notes
// - Same functions, same bits. Every per-element decision or force is a shared TUMBLE_HD
//   function of core/ (kernels/step.hpp, kernels/contact_list.hpp), called with the same
//   arguments as on the CPU; with --fmad=false (TUMBLE_STRICT_FP) the state is bit-identical to
//   the CPU pipeline's after every step. Both pipelines step a body in one pass (stepBody(): its
//   particles' forces summed in order as they come, then its integration), one thread per body
//   here: a body's force and torque stay in registers, no per-particle force is stored and read
//   back (the lever DEM-Engine measured for clumps), and the sums are the CPU's in its order.
// - Contacts as state. The candidate list is rebuilt only when the skin test asks (the drift
//   since the last rebuild: a max and a box of displacements, by integer atomics on
//   order-preserving images of the floats, exact in any order); the rows are sorted by scene
//   index, so the contacts and their order do not depend on the sweep's output order, the skin or
//   the internal numbering.
// - Determinism of the run itself: every output element has one writer, scans are integer scans,
//   sorts are stable, and the only atomics are an integer max/min and an integer count.
// - Host synchronisation: none between the steps of a batch (up to kMaxBatch = 64 steps of one
//   step() call): each step's skin test runs on the device (DecideFn) and, where it asks for a
//   rebuild, the batch's later steps do nothing; the host reads the batch's outcome (the steps
//   taken, their read-backs) once at its end and rebuilds before the next step. A batch lasts
//   about as long as the list did before (m_batch), so that few skipped steps are launched. With
//   moving walls, their walls and mesh poses for every step of the batch are computed on the
//   host and copied in one copy before it; each step's view points at its own. At a rebuild: the
//   broadphase's read-backs (bounds, record and entry totals), the lists' totals and the kept
//   histories' total.
// - Host memory handed to a copy stays as it is until the stream has reached the copy (members,
//   or locals that outlive a synchronize()): the host backend checks it (host_exec.hpp).
#pragma once
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "broadphase.hpp"
#include "periodic_images.hpp"
#include "exec/exec.hpp"
#include "tumble/error.hpp"
#include "tumble/guard.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/contact_sums.hpp"
#include "tumble/kernels/history.hpp"
#include "tumble/kernels/periodic_images.hpp"
#include "tumble/kernels/step.hpp"
#include "tumble/mesh.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble::gpu::detail {
inline namespace TUMBLE_EXEC_ABI {  // one copy per compiler (exec.hpp)

// --- Per-element functors: the stages' bodies, each a call of a shared function --------------

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

// The detection's input columns (radii grown by skin/2) and the build positions.
struct DetectionInputFn {
  const PosRow* pos;
  float halfSkin;
  float *x, *y, *z, *r;
  PosRow* buildPos;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    detectionInput(pos, i, halfSkin, x, y, z, r);
    buildPos[i] = pos[i];
  }
};

// Element n writes the trailing zero of the counts.
struct CandidateCountFn {
  SweepListView s;
  std::uint32_t n;
  std::uint32_t* counts;
  TUMBLE_HD void operator()(std::uint32_t i) const { counts[i] = i < n ? candidateCount(s, i) : 0u; }
};

struct CandidateFillFn {
  SweepListView s;
  const std::uint32_t* orig;
  const std::uint32_t* offsets;
  std::uint32_t* cand;
  std::uint32_t* key;
  TUMBLE_HD void operator()(std::uint32_t i) const { fillCandidates(s, orig, offsets, cand, key, i); }
};

// The reordering: the bounds of the body centres, Morton keys, then gathers in the sorted order.
struct BodyBoundsOp {
  const BodyRow* bodies;
  using Value = tumble::detail::BoundsPartial;
  static constexpr bool kAnyGrouping = true;  // min and max: exact in any grouping
  TUMBLE_HD Value identity() const { return tumble::detail::emptyBounds(); }
  TUMBLE_HD void add(Value& b, std::uint32_t k) const {
    tumble::detail::addParticle(b, k, bodies[k].x.x, bodies[k].x.y, bodies[k].x.z, 1.0f);
  }
  TUMBLE_HD void merge(Value& left, const Value& right) const { tumble::detail::mergeBounds(left, right); }
};

struct MortonKeyFn {
  const BodyRow* bodies;
  MortonGrid g;
  std::uint32_t* keys;
  std::uint32_t* vals;
  TUMBLE_HD void operator()(std::uint32_t k) const {
    keys[k] = mortonKey(g, bodies[k].x);
    vals[k] = k;
  }
};

// Element numBodies writes the trailing zero of the counts.
struct PermutedCountFn {
  const BodyRow* bodies;
  const std::uint32_t* perm;
  std::uint32_t numBodies;
  std::uint32_t* counts;
  TUMBLE_HD void operator()(std::uint32_t k) const { counts[k] = k < numBodies ? bodies[perm[k]].count : 0u; }
};

// The reordering's gathers (moveBody, kernels/contact_list.hpp), one body per element.
struct MoveBodiesFn {
  const BodyRow* bodies;
  const BodyStatic* bodyStatic;
  const std::uint32_t* perm;
  const std::uint32_t* first;
  std::uint32_t n, numPlanes;
  ReorderColumns from;
  BodyRow* outBodies;
  BodyStatic* outStatic;
  ReorderColumns to;
  TUMBLE_HD void operator()(std::uint32_t k) const {
    moveBody(bodies, bodyStatic, perm, first, k, n, numPlanes, from, outBodies, outStatic, to);
  }
};

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

// The histories across a rebuild (kernels/history.hpp), by scene index: kept from the rows of
// the old list (count → scan → fill: CudaPipeline::takeRows), restored into the rows of the new
// one; the same count → scan → fill reads them out (readLocalState()).
template <class KeyOf, class Take>
struct ListRows {
  const std::uint32_t* offsets;
  const Vec3f* hist;
  KeyOf keyOf;
  Take take;
  const std::uint32_t* orig;
};

// Element n writes the trailing zero of the counts.
template <class KeyOf, class Take>
struct TakenCountFn {
  ListRows<KeyOf, Take> r;
  std::uint32_t n;
  std::uint32_t* count;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    if (i == n) count[n] = 0;
    else count[r.orig[i]] = takenCount(r.offsets, r.hist, r.keyOf, r.take, i, r.orig[i]);
  }
};

template <class KeyOf, class Take>
struct TakeRowFn {
  ListRows<KeyOf, Take> r;
  const std::uint32_t* at;
  std::uint32_t* outKey;
  Vec3f* outHist;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    takeRow(r.offsets, r.hist, r.keyOf, r.take, i, r.orig[i], at[r.orig[i]], outKey, outHist);
  }
};

template <class KeyOf>
struct RestoreRowFn {
  KeptView kept;
  const std::uint32_t* orig;
  const std::uint32_t* offsets;
  KeyOf keyOf;
  Vec3f* hist;
  TUMBLE_HD void operator()(std::uint32_t i) const { restoreRow(kept, orig[i], offsets, keyOf, i, hist); }
};

// count[visit.slot(i)] = the number of elements visit(i, f) reports (the count of a count →
// scan → fill); element n writes the trailing zero of the counts.
template <class Visit>
struct VisitCountFn {
  Visit visit;
  std::uint32_t n;
  std::uint32_t* count;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    if (i == n) {
      count[n] = 0;
      return;
    }
    std::uint32_t c = 0;
    visit(i, [&](std::uint32_t) { ++c; });
    count[visit.slot(i)] = c;
  }
};

// The mesh candidate list (forMeshRow(), kernels/mesh.hpp) at a rebuild: count → scan → fill,
// each row sorted by triangle.
template <bool kPosed>
struct MeshRowVisit {
  MeshView mesh;
  const PosRow* pos;
  float grow;
  TUMBLE_HD std::uint32_t slot(std::uint32_t i) const { return i; }
  template <class F>
  TUMBLE_HD void operator()(std::uint32_t i, F&& f) const {
    forMeshRow<kPosed>(mesh, pos[i], grow, f);
  }
};

template <bool kPosed>
struct MeshRowFillFn {
  MeshRowVisit<kPosed> visit;
  const std::uint32_t* offsets;
  std::uint32_t* tri;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    std::uint32_t at = offsets[i];
    visit(i, [&](std::uint32_t t) { tri[at++] = t; });
    tumble::detail::sortRow(tri + offsets[i], nullptr, at - offsets[i]);
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

/// The CUDA pipeline over execution backend Exec (exec.hpp). `backend`: what backend() reports.
template <class Exec>
class CudaPipeline final : public HaloPipeline {
 public:
  using Stream = typename Exec::Stream;
  template <class T>
  using Buffer = typename Exec::template Buffer<T>;

 private:
  // Histories kept across a rebuild (kernels/history.hpp): CSR by scene index, each row's keys
  // ascending (tumble::detail::KeptRows on the device).
  struct KeptBuffers {
    Buffer<std::uint32_t> offsets, key;
    Buffer<Vec3f> hist;
    void upload(const tumble::detail::KeptRows& k, const Stream& s) {
      offsets.upload(k.offsets, s);
      key.upload(k.key, s);
      hist.upload(k.hist, s);
    }
    KeptView view() const { return {offsets.data(), key.data(), hist.data()}; }
  };

 public:
  CudaPipeline(Backend backend, const PipelineOptions& options)
      : m_backend(backend), m_ctx(options.threads), m_reorder(options.reorder) {}

  Backend backend() const override { return m_backend; }

  // As CpuPipeline::load.
  void load(const World& world) override {
    const exec::AbandonOnUnwind<Stream> unwind(m_ctx);  // copies from the locals below
    if (world.numParticles() == 0) throw Error("cannot load an empty world");
    requirePeriodsFit(world);  // before any state changes
    LocalFrame frame;
    World local = localWorld(world, &frame);  // far from the origin: integrate in a local frame
    m_loaded = false;
    m_steps = 0;  // the previous world's contacts are no longer read, whatever follows
    m_hasDebug = false;
    m_world = std::move(local);
    m_frame = frame;
    const World& w = m_world;
    const std::uint32_t n = w.numParticles(), nb = w.numBodies();
    const Stream& s = m_ctx;
    m_clumps = w.hasClumps || w.params.contact.rotatesSpheres();  // the rotating path
    m_law = w.params.contact.law;
    m_history = w.params.contact.hasHistory();
    // Every host array copied from here lives until the synchronize() below.
    m_planesNow = kernelWalls(world.params, m_frame);  // from the world's points: as the guard sees them
    m_numPlanes = static_cast<std::uint32_t>(m_planesNow.size());
    m_wallsMove = world.params.wallsMove();
    m_planes.upload(m_planesNow, s);
    m_planeDamping.upload(w.planeDamping, s);
    std::vector<BodyRow> bodies;
    std::vector<BodyStatic> bodyStatic;
    std::vector<OwnRow> own;
    tumble::detail::initialRows(w, &bodies, &bodyStatic, &own);
    std::vector<std::uint32_t> orig(n);
    for (std::uint32_t i = 0; i < n; ++i) orig[i] = i;
    const BodyState& st = w.state;
    m_bodies.upload(bodies, s);
    m_bodiesNext.grow(nb);
    m_bodyStatic.upload(bodyStatic, s);
    m_own.upload(own, s);
    m_radius.upload(w.radius, s);
    m_mass.upload(w.mass, s);
    m_orig.upload(orig, s);
    m_bodyOf.upload(w.body, s);
    // One material: every particle's is 0 and the kernels need no column; as the CPU pipeline,
    // the column is the world's (filled for the laws that use materials only).
    m_hasMaterial = w.params.materials.size() > 1 && !w.material.empty();
    m_material.upload(w.material.data(), m_hasMaterial ? w.material.size() : 0, s);
    m_hertz.upload(w.materialPairs, s);
    m_planeHertz.upload(w.planeHertz, s);
    // A loaded state's contact histories, kept as before a rebuild (restored by the first).
    const tumble::detail::KeptRows kept = m_history ? tumble::detail::keptOfContacts(n, st.contacts)
                                                    : tumble::detail::KeptRows{};
    m_kept.upload(kept, s);
    // Mesh walls: their triangles and hierarchy, from the world's scene and the run's frame (as
    // the guard's); the springs of a loaded state kept for the first rebuild.
    const KernelMesh mesh = kernelMesh(world.params, m_frame);
    m_mesh.upload(mesh, s);
    const tumble::detail::KeptRows meshKept = tumble::detail::keptOfMeshContacts(n, st.meshContacts);  // a local: copied later
    m_meshKept.upload(meshKept, s);
    Exec::fillZero(s, m_meshOffsets.grow(std::size_t(n) + 1), std::size_t(n) + 1);
    m_numMeshCand = 0;
    m_listBuilt = false;
    m_numSprings = st.groundSpringX.size();  // localWorld sized them: planes × particles
    m_tx.upload(st.groundSpringX, s);
    m_ty.upload(st.groundSpringY, s);
    for (auto& p : m_pos) p.grow(n);
    m_buildPos.grow(n);
    m_touching.grow(n);
    m_candOffsets.grow(std::size_t(n) + 1);
    m_cur = 0;  // before the positions: a reload after an odd number of steps writes m_pos[0] too
    m_clumps ? launchState<true>() : launchState<false>();  // readLocalPositions() before the first step
    s.synchronize();
    m_numCand = 0;
    m_skin = effectiveSkin(w);
    // Periodic boundaries (periodic_images.hpp), as CpuPipeline::load.
    m_periodic = kernelPeriodic(w.params, m_frame);
    m_periodicGrowth = m_periodic.axes != 0 ? periodicGrowth(w.maxRadius + 0.5f * m_skin, m_periodic) : 0.0f;
    m_skinLimit = skinClosureLimit(m_skin, w.maxRadius, periodicRoundingReach(m_periodic));
    // Moving meshes: their poses at each step's start (setWallMotion()), and their motion in the
    // skin test (MeshMotionBound).
    m_meshMotion = MeshMotionBound(w.params, mesh, m_planesNow, w.maxRadius, m_skin);
    m_numPoses = m_meshMotion.any() ? m_numPlanes : 0u;
    m_wallsAt = m_planes.data();  // until a batch of moving walls points at its own
    m_posesAt = nullptr;
    m_batch = 8;
    m_needRebuild = true;
    m_pulls = w.params.pulls.active & ~w.params.periodic.conflictingPulls();
    m_time = w.time;
    m_bp.reset();
    resetStats();
    m_loaded = true;
  }

  void step(std::uint64_t n) override {
    const exec::AbandonOnUnwind<Stream> unwind(m_ctx);  // read-backs into stepBatch's locals
    if (!m_loaded) throw Error("step() before load()");
    while (n > 0) n -= stepBatch(static_cast<std::uint32_t>(std::min<std::uint64_t>(n, m_batch)));
  }

  void readState(BodyState& out) const override {
    readLocalState(out);
    toWorld(out, m_frame);
  }
  LocalFrame frame() const override { return m_frame; }

  void readLocalState(BodyState& out) const override {
    const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
    if (!m_loaded) {
      out = BodyState{};  // as the CPU pipeline's empty state before load()
      return;
    }
    const std::uint32_t nb = m_world.numBodies(), n = m_world.numParticles();
    const Stream& s = m_ctx;
    std::vector<BodyRow> bodies(nb);
    std::vector<std::uint32_t> orig(n);
    std::vector<float> tx(m_numSprings), ty(m_numSprings);
    m_bodies.download(bodies.data(), nb, s);
    m_orig.download(orig.data(), n, s);
    m_tx.download(tx.data(), tx.size(), s);
    m_ty.download(ty.data(), ty.size(), s);
    s.synchronize();
    out.resize(nb);
    out.imageX.resize(m_periodic.on(0) ? nb : 0);
    out.imageY.resize(m_periodic.on(1) ? nb : 0);
    for (const BodyRow& b : bodies) {
      const std::uint32_t o = b.orig;
      out.px[o] = b.x.x; out.py[o] = b.x.y; out.pz[o] = b.x.z;
      out.vx[o] = b.v.x; out.vy[o] = b.v.y; out.vz[o] = b.v.z;
      out.qw[o] = b.q.w; out.qx[o] = b.q.x; out.qy[o] = b.q.y; out.qz[o] = b.q.z;
      out.lx[o] = b.l.x; out.ly[o] = b.l.y; out.lz[o] = b.l.z;
      if (m_periodic.on(0)) out.imageX[o] = b.image[0];
      if (m_periodic.on(1)) out.imageY[o] = b.image[1];
    }
    out.contacts = m_history ? readRows<ContactHistory>(m_kept, partnerRows(TakeAbove{}), tumble::detail::MakeContact{})
                             : std::vector<ContactHistory>{};
    out.meshContacts = hasMesh() ? readRows<MeshContactHistory>(m_meshKept, meshRows(), tumble::detail::MakeMeshContact{})
                                 : std::vector<MeshContactHistory>{};
    out.groundSpringX.resize(tx.size());
    out.groundSpringY.resize(ty.size());
    for (std::size_t k = 0; k < tx.size(); ++k) {
      const std::size_t o = (k / n) * n + orig[k % n];  // plane-major
      out.groundSpringX[o] = tx[k];
      out.groundSpringY[o] = ty[k];
    }
  }

  // As CpuPipeline::readLocalPositions.
  void readLocalPositions(std::vector<float>& out) const override {
    const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
    const std::uint32_t n = m_world.numParticles();
    std::vector<PosRow> pos(n);
    std::vector<std::uint32_t> orig(n);
    m_pos[m_cur].download(pos.data(), n, m_ctx);
    m_orig.download(orig.data(), n, m_ctx);
    m_ctx.synchronize();
    out.resize(3 * std::size_t(n));
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::size_t o = 3 * std::size_t(orig[i]);
      out[o] = pos[i].x;
      out[o + 1] = pos[i].y;
      out[o + 2] = pos[i].z;
    }
  }

  // As CpuPipeline::pairs.
  std::vector<Pair> pairs() const override {
    if (m_steps == 0) return {};
    const CandidateListView list = compactList(m_candOffsets.data(), m_cand.data());
    const PosRow* pos = m_pos[1 - m_cur].data();  // the rows the last step used
    return contactsOf(pos, m_orig.data(), list, m_touching.data(), m_periodic, m_world.numParticles());
  }

  // As CpuPipeline::meshContacts: the (particle, triangle) contacts of the last step, at its
  // positions and poses, sorted.
  std::vector<MeshContact> meshContacts() const override {
    if (m_steps == 0 || !hasMesh()) return {};
    const std::uint32_t n = m_world.numParticles();
    const Stream& s = m_ctx;
    const PosRow* pos = m_pos[1 - m_cur].data();  // the rows the last step used, with its mesh rows
    const MeshView mv = meshView();                // and its poses
    Buffer<std::uint32_t> count, at;
    Buffer<MeshContact> hits;
    Buffer<unsigned char> temp;
    // After the buffers: on an exception the queue is dropped before they free (and drain) it.
    const exec::AbandonOnUnwind<Stream> unwind(s);
    std::uint32_t* c = count.grow(std::size_t(n) + 1);
    std::uint32_t* a = at.grow(std::size_t(n) + 1);
    const MeshHitsVisit hitsOf{mv, m_meshOffsets.data(), m_meshTri.data(), pos, m_orig.data()};
    Exec::forEach(s, std::uint64_t(n) + 1, VisitCountFn<MeshHitsVisit>{hitsOf, n, c}, "meshHitsCount");
    Exec::exclusiveSum(s, temp, c, a, n + 1);
    std::uint32_t total = 0;
    Exec::copyToHost(s, &total, a + n, 1);
    s.synchronize();
    std::vector<MeshContact> out(total);
    if (total > 0) {
      Exec::forEach(s, n, MeshHitsFillFn{hitsOf, a, hits.grow(total)}, "meshHitsFill");
      hits.download(out.data(), total, s);
      s.synchronize();
    }
    return out;
  }

  // The hooks of a domain decomposition (HaloPipeline; tumble::mpi), as CpuPipeline's.
  void readMotion(const std::vector<std::uint32_t>& bodies, std::vector<BodyMotion>& out) const override {
    const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
    const auto m = static_cast<std::uint32_t>(bodies.size());
    out.resize(m);
    if (m == 0) return;
    const Stream& s = m_ctx;
    const std::uint32_t* at = bodyIndex();
    m_halo.list.upload(bodies, s);
    Exec::forEach(s, m, ReadMotionFn{m_bodies.data(), at, m_halo.list.data(), m_halo.motion.grow(m)}, "readMotion");
    m_halo.motion.download(out.data(), m, s);
    s.synchronize();
  }

  void writeMotion(const std::vector<std::uint32_t>& bodies, const std::vector<BodyMotion>& motion) override {
    const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
    const auto m = static_cast<std::uint32_t>(bodies.size());
    const Stream& s = m_ctx;
    if (m > 0) {
      const std::uint32_t* at = bodyIndex();
      m_halo.list.upload(bodies, s);
      m_halo.motion.upload(motion.data(), m, s);
      PosRow* pos = m_pos[m_cur].data();
      if (m_clumps)
        Exec::forEach(s, m,
                      WriteMotionFn<true>{m_bodies.data(), at, m_halo.list.data(), m_halo.motion.data(), m_own.data(),
                                          m_radius.data(), pos},
                      "writeMotion");
      else
        Exec::forEach(s, m,
                      WriteMotionFn<false>{m_bodies.data(), at, m_halo.list.data(), m_halo.motion.data(), m_own.data(),
                                           m_radius.data(), pos},
                      "writeMotion");
    }
    if (m_steps == 0) {  // the first step rebuilds anyway
      s.synchronize();
      return;
    }
    // The skin test of the step just taken, again, on the positions as they are now.
    StepReadback* rb = clearReadbacks(1);
    Exec::forEach(s, m_world.numParticles(), ParticleDriftFn{m_pos[m_cur].data(), m_buildPos.data(), m_periodic, rb},
                  "particleDrift");
    StepReadback h{};
    Exec::copyToHost(s, &h, rb, 1);
    s.synchronize();
    // The step just taken has advanced m_time: the next step's start.
    m_needRebuild = rebuildDue(driftOf(h), hasMesh(), meshClosureUntil(m_time), m_skinLimit);
  }

  std::uint64_t contactsOf(const std::vector<std::uint32_t>& bodies) const override {
    const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
    const auto m = static_cast<std::uint32_t>(bodies.size());
    if (m_steps == 0 || m == 0) return 0;
    const Stream& s = m_ctx;
    const std::uint32_t* at = bodyIndex();
    m_halo.list.upload(bodies, s);
    unsigned long long* total = m_halo.total.grow(1);
    Exec::fillZero(s, total, 1);
    Exec::forEach(s, m,
                  BodyContactCountFn{m_bodies.data(), at, m_halo.list.data(), m_touching.data(), m_pos[1 - m_cur].data(),
                                     compactList(m_candOffsets.data(), m_cand.data()), m_periodic, total},
                  "contactsOf");
    unsigned long long h = 0;
    Exec::copyToHost(s, &h, total, 1);
    s.synchronize();
    return h;
  }

  // As CpuPipeline::contactSumsPerBody: the guard's sums per body where the contacts lie, one
  // writer per body; the law's tables (host memory) copied for the kernel.
  bool contactSumsPerBody(const SpringLaw& law, std::vector<ContactSums>& out) const override {
    const std::uint32_t nb = m_world.numBodies();
    if (m_steps == 0) {  // no contacts yet, as pairs()
      out.assign(nb, ContactSums{});
      return true;
    }
    const Stream& s = m_ctx;
    Buffer<HertzPair> hertz;
    Buffer<std::uint16_t> material;
    Buffer<ContactSums> sums;
    // After the buffers: on an exception the queue is dropped before they free (and drain) it.
    const exec::AbandonOnUnwind<Stream> unwind(s);
    SpringLaw onDevice = law;
    if (law.hertz != nullptr) {
      hertz.upload(law.hertz, std::size_t(law.numMaterials + 1) * (law.numMaterials + 1), s);
      onDevice.hertz = hertz.data();
    }
    if (law.material != nullptr) {
      material.upload(law.material, m_world.numParticles(), s);
      onDevice.material = material.data();
    }
    Exec::forEach(s, nb,
                  BodyContactSumsFn{m_bodies.data(), m_bodyOf.data(), m_touching.data(), m_pos[1 - m_cur].data(),
                                    m_pos[m_cur].data(), m_orig.data(), compactList(m_candOffsets.data(), m_cand.data()),
                                    onDevice, m_periodic, sums.grow(nb)},
                  "contactSums");
    out.resize(nb);
    sums.download(out.data(), nb, s);
    s.synchronize();
    return true;
  }

  // As CpuPipeline::findPairs (same checks, same messages, a fresh broadphase).
  std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) override {
    const float maxR = checkCloud(cloud);
    const std::size_t n = cloud.size();
    if (n == 0) return {};
    const Stream& s = m_ctx;
    Buffer<float> x, y, z, r;
    Buffer<std::uint32_t> body;
    Broadphase<Exec> b;
    // After the buffers: on an exception the queue is dropped before they free (and drain) it.
    const exec::AbandonOnUnwind<Stream> unwind(s);
    x.upload(cloud.x, s);
    y.upload(cloud.y, s);
    z.upload(cloud.z, s);
    r.upload(cloud.r, s);
    body.upload(cloud.body, s);
    const BroadphaseInput in{x.data(), y.data(), z.data(), r.data(), body.data(), static_cast<std::uint32_t>(n), maxR,
                             tumble::detail::sizingRadius(cloud.r.data(), n)};
    if (cloud.periodic.axes != 0) return findPeriodicPairs(cloud, in, bp, b);
    b.run(in, bp, s, nullptr);
    return b.sortedPairs(static_cast<std::uint32_t>(n), s);
  }

  void setDebugCapture(bool on) override { m_debug = on; }

  // As CpuPipeline::readDebug.
  void readDebug(ParticleDebug& out) const override {
    const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
    if (!m_hasDebug) throw Error("readDebug(): enable setDebugCapture(true) and run a step first");
    const std::uint32_t n = m_world.numParticles();
    const Stream& s = m_ctx;
    std::vector<float> v(3 * std::size_t(n)), f[5];
    std::vector<std::uint32_t> orig(n);
    m_dbgVel.download(v.data(), v.size(), s);
    for (int k = 0; k < 5; ++k) {
      f[k].resize(3 * std::size_t(n));
      m_dbg[k].download(f[k].data(), f[k].size(), s);
    }
    m_orig.download(orig.data(), n, s);
    s.synchronize();
    out.v.resize(3 * std::size_t(n));
    for (auto& c : out.force) c.resize(3 * std::size_t(n));
    for (std::uint32_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        const std::size_t o = 3 * std::size_t(orig[i]) + c, a = 3 * std::size_t(i) + c;
        out.v[o] = v[a];
        for (int k = 0; k < 5; ++k) out.force[k][o] = f[k][a];
      }
    out.contacts = pairs();
  }

  // A pull along a periodic axis is left off (its potential has no period; scene files refuse it).
  void setPulls(std::uint32_t mask) override { m_pulls = mask & 7u & ~m_world.params.periodic.conflictingPulls(); }
  std::uint32_t pulls() const override { return m_pulls; }
  const StepStats& stats() const override { return m_stats; }
  void resetStats() override {
    m_stats = StepStats{};
    m_stats.skin = m_skin;
  }
  double time() const override { return m_time; }
  std::uint64_t stepCount() const override { return m_world.step + m_steps; }

 private:
  // The contacts of the rows `list` at the positions pos (touching: the particles to walk, nullptr
  // for all) as sorted scene-index pairs: per particle its contacts with a higher scene index,
  // counted, scanned by scene index and written there (count → scan → fill).
  std::vector<Pair> contactsOf(const PosRow* pos, const std::uint32_t* orig, const CandidateListView& list,
                               const std::uint8_t* touching, const PeriodicBox& box, std::uint32_t n) const {
    const Stream& s = m_ctx;
    Buffer<std::uint32_t> count, at, outI, outJ;
    Buffer<unsigned char> temp;
    // After the buffers: on an exception the queue is dropped before they free (and drain) it.
    const exec::AbandonOnUnwind<Stream> unwind(s);
    std::uint32_t* c = count.grow(std::size_t(n) + 1);
    std::uint32_t* a = at.grow(std::size_t(n) + 1);
    Exec::forEach(s, std::uint64_t(n) + 1, ContactsAboveFn{pos, orig, list, touching, box, n, c}, "contactsAbove");
    Exec::exclusiveSum(s, temp, c, a, n + 1);
    std::uint32_t total = 0;
    Exec::copyToHost(s, &total, a + n, 1);
    s.synchronize();
    std::vector<std::uint32_t> hi(total), hj(total);
    if (total > 0) {
      Exec::forEach(s, n, EmitContactsFn{pos, orig, list, touching, box, a, outI.grow(total), outJ.grow(total)},
                    "emitContacts");
      outI.download(hi.data(), total, s);
      outJ.download(hj.data(), total, s);
      s.synchronize();
    }
    std::vector<Pair> out(total);
    for (std::uint32_t k = 0; k < total; ++k) out[k] = Pair{hi[k], hj[k]};
    return out;
  }

  // As CpuPipeline::findPeriodicPairs: the sweep over the images on radii grown by the rounding
  // margin of a difference across the boundary, then the exact predicate (the minimum image, as
  // the oracle) on each particle's merged row.
  std::vector<Pair> findPeriodicPairs(const ParticleCloud& cloud, const BroadphaseInput& in, const BroadphaseParams& bp,
                                      Broadphase<Exec>& b) {
    const std::uint32_t n = in.n;
    const Stream& s = m_ctx;
    const PeriodicBox& box = cloud.periodic;
    const float g = periodicGrowth(in.maxRadius, box);
    std::vector<float> grown(n);
    std::vector<PosRow> rows(n);
    std::vector<std::uint32_t> orig(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      grown[i] = cloud.r[i] + g;
      rows[i] = PosRow{cloud.x[i], cloud.y[i], cloud.z[i], cloud.r[i]};
      orig[i] = i;
    }
    Buffer<float> r;
    Buffer<PosRow> pos;
    Buffer<std::uint32_t> ids, offsets, cand, key;
    PeriodicImages<Exec> images;
    // After the buffers: on an exception the queue is dropped before they free (and drain) it.
    const exec::AbandonOnUnwind<Stream> unwind(s);
    r.upload(grown, s);
    pos.upload(rows, s);
    ids.upload(orig, s);
    const BroadphaseInput gin{in.x, in.y, in.z, r.data(), in.body, n, in.maxRadius + g,
                              in.cellRadius > 0.0f ? in.cellRadius + g : 0.0f};
    images.build(gin, box, ghostReach(gin.maxRadius, box), s);
    b.run(images.input(), bp, s, nullptr);
    images.rows(b.listView(), ids.data(), offsets, cand, key, s);
    return contactsOf(pos.data(), ids.data(), compactList(offsets.data(), cand.data()), nullptr, box, n);
  }

  StepView stepView() {
    const int c = m_cur;
    return StepView{m_bodies.data(),
                    m_bodiesNext.data(),
                    m_bodyStatic.data(),
                    m_world.numBodies(),
                    m_pos[c].data(),
                    m_pos[1 - c].data(),
                    m_own.data(),
                    m_radius.data(),
                    m_mass.data(),
                    m_bodyOf.data(),
                    m_orig.data(),
                    m_numSprings > 0 ? GroundSpringView{m_tx.data(), m_ty.data()} : GroundSpringView{nullptr, nullptr},
                    m_buildPos.data(),
                    compactList(m_candOffsets.data(), m_cand.data()),
                    m_touching.data(),
                    m_world.numParticles(),
                    m_history ? m_hist.data() : nullptr,
                    m_world.params.contact.rotatesSpheres(),
                    m_world.materialPairs.empty() ? nullptr : m_hertz.data(),
                    m_hasMaterial ? m_material.data() : nullptr,
                    static_cast<std::uint32_t>(m_world.params.materials.size()),
                    m_wallsAt,
                    m_numPlanes,
                    m_numPlanes > 1 ? m_planeDamping.data() : nullptr,  // planes 1.. (plane 0's is in the own rows)
                    m_world.planeHertz.empty() ? nullptr : m_planeHertz.data(),
                    m_periodic,
                    meshView(),
                    MeshListView{m_meshOffsets.data(), m_meshTri.data(), hasMesh() ? m_meshHist.data() : nullptr},
                    nullptr,   // the skin test per particle (buildPos)
                    nullptr};  // the list's rows are walked one by one (no owners)
  }

  // As CpuPipeline::stepOnce, `count` times in a row with no host round trip between the steps:
  // each step's kernel, then its skin test on the device (DecideFn). Where a step's test asks for
  // a rebuild, the batch's later steps do nothing, and the host, which reads the batch's outcome
  // once at its end, rebuilds before the next step. Returns the steps taken (at least 1).
  std::uint32_t stepBatch(std::uint32_t count) {
    const std::uint32_t n = m_world.numParticles();
    const Stream& s = m_ctx;
    const Scene& p = m_world.params;
    // The batch's step times (as the steps add dt one by one), the moving walls and meshes at
    // each step's start, and the meshes' motion since the rebuild up to each step's end. Host
    // arrays copied from here stay as they are until the synchronize() below.
    m_batchTimes.resize(count + 1);
    m_batchTimes[0] = m_time;
    for (std::uint32_t k = 0; k < count; ++k) m_batchTimes[k + 1] = m_batchTimes[k] + p.dt;
    const std::size_t planes = m_numPlanes, poses = m_numPoses;
    if (m_wallsMove) {
      m_batchWalls.resize(count * planes);
      m_batchPoses.resize(count * poses);
      for (std::uint32_t k = 0; k < count; ++k) {
        std::vector<Wall>& now = m_planesNow;
        setWallMotion(now, p, m_batchTimes[k], poses == 0 ? nullptr : &m_batchPoses[k * poses]);
        std::copy(now.begin(), now.end(), m_batchWalls.begin() + std::ptrdiff_t(k * planes));
      }
    }
    // One copy for the batch; each step reads its own walls and poses (at the first step's
    // start, before a rebuild reads them).
    if (m_wallsMove) {
      m_batchWallsDev.upload(m_batchWalls, s);
      m_batchPosesDev.upload(m_batchPoses, s);
      setWallsOfStep(0);
    }
    if (m_needRebuild) {
      rebuild();
    } else {
      for (Phase ph : {Phase::Reorder, Phase::State, Phase::Axis, Phase::Keys, Phase::Sort, Phase::Sweep, Phase::List})
        m_timer.mark(ph, s);  // no rebuild this step: the phases take no time
    }
    m_batchMeshes.resize(count);
    for (std::uint32_t k = 0; k < count; ++k) m_batchMeshes[k] = meshClosureUntil(m_batchTimes[k + 1]);
    m_meshClosure.upload(m_batchMeshes, s);
    StepReadback* rb = clearReadbacks(count);
    std::uint32_t* stop = m_stop.grow(1);
    Exec::fillZero(s, stop, 1);

    m_timer.mark(Phase::Forces, s);
    const ForceParams fp = makeForceParams(p, m_pulls);
    DebugForcesView dbg{{nullptr, nullptr, nullptr, nullptr, nullptr}, nullptr};
    if (m_debug) {
      for (int k = 0; k < 5; ++k) dbg.f[k] = m_dbg[k].grow(3 * std::size_t(n));
      dbg.v = m_dbgVel.grow(3 * std::size_t(n));
    }
    for (std::uint32_t k = 0; k < count; ++k) {
      if (m_wallsMove) setWallsOfStep(k);
      const StepView v = stepView();
      m_debug ? launchStep<true>(v, fp, dbg, rb + k, stop) : launchStep<false>(v, fp, dbg, rb + k, stop);
      Exec::forEach(s, 1, DecideFn{rb, m_meshClosure.data(), k, m_skinLimit, hasMesh(), stop}, "decide");
      m_cur = 1 - m_cur;  // as if the step is taken; corrected below for the steps that were not
      std::swap(m_bodies, m_bodiesNext);
    }
    m_timer.mark(Phase::Integrate, s);  // in the forces' kernel: no time of its own, as on the CPU

    std::uint32_t stopped = 0;
    Exec::copyToHost(s, &stopped, stop, 1);
    m_readbackHost.resize(count);
    Exec::copyToHost(s, m_readbackHost.data(), rb, count);
    m_timer.finish(s);
    m_timer.accumulate(s, m_stats.seconds);  // waits for the batch (and the read-backs)
    const std::uint32_t taken = stopped != 0 ? stopped : count;
    if ((count - taken) % 2 != 0) {  // the buffers of the last step taken
      m_cur = 1 - m_cur;
      std::swap(m_bodies, m_bodiesNext);
    }
    const StepReadback& h = m_readbackHost[taken - 1];
    m_needRebuild = stopped != 0;
    // The next batch about as long as the list lasted (its steps after a rebuild are skipped, but
    // launched): the bits do not depend on it.
    m_batch = stopped != 0 ? std::max(1u, taken) : std::min(2 * m_batch, kMaxBatch);
    m_hasDebug = m_debug;  // readDebug() reads the last step's capture, or refuses
    m_steps += taken;
    m_time = m_batchTimes[taken];
    m_stats.steps += taken;
    m_stats.numPairs = h.contacts / 2;  // each contact is seen from both sides
    return taken;
  }

  // The walls and meshes' poses at the start of step k of the batch, as the step views see them.
  // After step() they are the last step's (what meshContacts() reads): its last batch ran to its
  // end, since one stopped early is followed by another.
  void setWallsOfStep(std::uint32_t k) {
    m_wallsAt = m_batchWallsDev.data() + std::size_t(k) * m_numPlanes;
    m_posesAt = m_numPoses == 0 ? nullptr : m_batchPosesDev.data() + std::size_t(k) * m_numPoses;
  }

  // `count` steps' read-backs on the device, reset (no drift, no contacts).
  StepReadback* clearReadbacks(std::uint32_t count) {
    const Drift none = noDrift();
    StepReadback init{orderedBits(none.max2), {}, {}, 0u, 0ull};
    for (int a = 0; a < 3; ++a) {
      init.lo[a] = orderedBits(none.lo[a]);
      init.hi[a] = orderedBits(none.hi[a]);
    }
    m_readbackInit.assign(count, init);  // a member: the stream may reach the copy after this function returns
    Exec::copyToDevice(m_ctx, m_readback.grow(count), m_readbackInit.data(), count);
    return m_readback.data();
  }

  // The moving meshes' closure since the rebuild up to time `next` (rebuildDue()); 0 without.
  double meshClosureUntil(double next) const {
    return m_meshMotion.any() ? m_meshMotion.closure(m_rebuildTime, next) : 0.0;
  }

  // The internal index of each body by scene index (the hooks of a domain decomposition).
  const std::uint32_t* bodyIndex() const {
    const std::uint32_t nb = m_world.numBodies();
    Exec::forEach(m_ctx, nb, BodyIndexFn{m_bodies.data(), m_halo.at.grow(nb)}, "bodyIndex");
    return m_halo.at.data();
  }

  // Stages 3–7 (StepBodyFn), instantiated for the scene's law (the laws with history rotate
  // every body, as on the CPU), for periodic boundaries and for moving meshes (kPosedMesh: a
  // scene whose meshes stand still runs the code without poses; a periodic scene has no mesh).
  template <bool kDebug>
  void launchStep(const StepView& v, const ForceParams& fp, const DebugForcesView& dbg, StepReadback* rb,
                  const std::uint32_t* stop) {
    if (m_periodic.axes != 0) return launchStepLaw<kDebug, true, false>(v, fp, dbg, rb, stop);
    m_numPoses == 0 ? launchStepLaw<kDebug, false, false>(v, fp, dbg, rb, stop)
                           : launchStepLaw<kDebug, false, true>(v, fp, dbg, rb, stop);
  }
  template <bool kDebug, bool kPeriodic, bool kPosed>
  void launchStepLaw(const StepView& v, const ForceParams& fp, const DebugForcesView& dbg, StepReadback* rb,
                     const std::uint32_t* stop) {
    switch (m_law) {
      case ContactLaw::HookeHistory:
        return launchStepOf<kDebug, true, ContactLaw::HookeHistory, kPeriodic, kPosed>(v, fp, dbg, rb, stop);
      case ContactLaw::HertzMindlin:
        return launchStepOf<kDebug, true, ContactLaw::HertzMindlin, kPeriodic, kPosed>(v, fp, dbg, rb, stop);
      default:
        return m_clumps ? launchStepOf<kDebug, true, ContactLaw::Report, kPeriodic, kPosed>(v, fp, dbg, rb, stop)
                        : launchStepOf<kDebug, false, ContactLaw::Report, kPeriodic, kPosed>(v, fp, dbg, rb, stop);
    }
  }
  template <bool kDebug, bool kClumps, ContactLaw kLaw, bool kPeriodic, bool kPosed>
  void launchStepOf(const StepView& v, const ForceParams& fp, const DebugForcesView& dbg, StepReadback* rb,
                    const std::uint32_t* stop) {
    const Scene& p = m_world.params;
    Exec::forEach(m_ctx, m_world.numBodies(),
                  StepBodyFn<kDebug, kClumps, kLaw, kPeriodic, kPosed>{v, fp, dbg, p.gravity, p.dt,
                                                                       p.integrator.rotation, rb, stop},
                  "step");
  }

  // Stage 1: the particle positions of the current body state (after a reordering, and at load).
  template <bool kClumps>
  void launchState() {
    Exec::forEach(m_ctx, m_world.numBodies(),
                  StateFn<kClumps>{m_bodies.data(), m_own.data(), m_radius.data(), m_pos[m_cur].data()}, "state");
  }

  // As CpuPipeline::rebuild.
  void rebuild() {
    const std::uint32_t n = m_world.numParticles();
    const Stream& s = m_ctx;
    m_timer.mark(Phase::Reorder, s);
    if (m_listBuilt && (m_history || hasMesh())) {  // by scene index: survives the renumbering
      if (m_history) keepHistory();
      if (hasMesh()) keepMeshHistory();
      m_listBuilt = false;  // until the new lists hold them (a failed rebuild keeps the kept ones)
    }
    if (m_reorder) reorder();

    m_timer.mark(Phase::State, s);
    m_clumps ? launchState<true>() : launchState<false>();
    // Detection input: the positions and the radii grown by skin/2 (and with periodic boundaries
    // by the rounding of a difference across them, periodicGrowth()).
    const float h = 0.5f * m_skin + m_periodicGrowth;
    Exec::forEach(s, n,
                  DetectionInputFn{m_pos[m_cur].data(), h, m_bx.grow(n), m_by.grow(n), m_bz.grow(n), m_br.grow(n),
                                   m_buildPos.data()},
                  "detectionInput");

    const BroadphaseInput in{m_bx.data(), m_by.data(), m_bz.data(), m_br.data(), m_bodyOf.data(), n,
                             m_world.maxRadius + h,
                             m_world.sizingRadius > 0.0f ? m_world.sizingRadius + h : 0.0f};
    try {
      if (m_periodic.axes != 0) {  // the sweep over the particles and their ghost images
        m_images.build(in, m_periodic, ghostReach(in.maxRadius, m_periodic), s);
        m_bp.run(m_images.input(), m_world.params.broadphase, s, &m_timer);
      } else {
        m_bp.run(in, m_world.params.broadphase, s, &m_timer);
      }
    } catch (const SimulationError& e) {
      if (e.particle() < 0) throw;
      std::uint32_t o = 0;
      Exec::copyToHost(s, &o, m_orig.data() + e.particle(), 1);
      s.synchronize();
      throw SimulationError(divergenceMessage(m_world, m_world.step + m_steps, o), o);
    }

    m_timer.mark(Phase::List, s);
    const SweepListView sl = m_bp.listView();
    if (m_periodic.axes != 0) {
      m_numCand = m_images.rows(sl, m_orig.data(), m_candOffsets, m_cand, m_candKey, s);
    } else {
      std::uint32_t* count = m_count.grow(std::size_t(n) + 1);
      Exec::forEach(s, std::uint64_t(n) + 1, CandidateCountFn{sl, n, count}, "candidateCount");
      Exec::exclusiveSum(s, m_temp, count, m_candOffsets.data(), n + 1);
      Exec::copyToHost(s, &m_numCand, m_candOffsets.data() + n, 1);
      s.synchronize();
      Exec::forEach(s, n,
                    CandidateFillFn{sl, m_orig.data(), m_candOffsets.data(), m_cand.grow(m_numCand),
                                    m_candKey.grow(m_numCand)},
                    "candidateFill");
    }
    if (m_history) restoreHistory();
    if (hasMesh()) {
      m_numPoses == 0 ? buildMeshList<false>() : buildMeshList<true>();
      restoreMeshHistory();
    }
    m_listBuilt = true;
    m_rebuildTime = m_time;
    m_needRebuild = false;
    ++m_stats.numRebuilds;
    m_stats.numCandidates = m_numCand / 2;
    m_stats.numRecords = m_bp.numRecords();
    m_stats.numCells = m_bp.numCells();
    m_stats.cellSize = m_bp.frame().cellSize;
  }

  // As CpuPipeline::buildMeshList: the mesh candidate list at the rebuild's positions.
  template <bool kPosed>
  void buildMeshList() {
    const std::uint32_t n = m_world.numParticles();
    const Stream& s = m_ctx;
    const MeshView mv = meshView();
    const PosRow* pos = m_pos[m_cur].data();
    const float grow = tumble::detail::meshRowGrowth(m_skin, m_world.maxRadius);
    std::uint32_t* count = m_count.grow(std::size_t(n) + 1);
    const MeshRowVisit<kPosed> rows{mv, pos, grow};
    Exec::forEach(s, std::uint64_t(n) + 1, VisitCountFn<MeshRowVisit<kPosed>>{rows, n, count}, "meshRowCount");
    Exec::exclusiveSum(s, m_temp, count, m_meshOffsets.data(), n + 1);
    Exec::copyToHost(s, &m_numMeshCand, m_meshOffsets.data() + n, 1);
    s.synchronize();
    Exec::forEach(s, n, MeshRowFillFn<kPosed>{rows, m_meshOffsets.data(), m_meshTri.grow(m_numMeshCand)}, "meshRowFill");
  }

  // The meshes as the kernels see them, posed where some move (the poses of the step's start).
  MeshView meshView() const {
    MeshView v = meshViewOf(m_mesh);
    if (m_numPoses > 0 && v.numTriangles > 0) {
      v.poses = m_posesAt;
      v.numPoses = m_numPoses;
    }
    return v;
  }

  // The rows of the candidate list (ξ keyed by the partner's scene index) and of the mesh
  // candidate list (keyed by the triangle), as takeRows() reads them.
  template <class Take>
  ListRows<PartnerKey, Take> partnerRows(Take take) const {
    return {m_candOffsets.data(), m_hist.data(), PartnerKey{m_orig.data(), m_cand.data()}, take, m_orig.data()};
  }
  ListRows<TriangleKey, TakeAll> meshRows() const {
    return {m_meshOffsets.data(), m_meshHist.data(), TriangleKey{m_meshTri.data()}, TakeAll{}, m_orig.data()};
  }

  // The non-zero ξ of the rows that `rows.take` accepts (kernels/history.hpp), by scene index
  // with their keys: count → scan → fill into out (offsets of n + 1). Returns their number.
  template <class KeyOf, class Take>
  std::uint32_t takeRows(const ListRows<KeyOf, Take>& rows, Buffer<std::uint32_t>& count, Buffer<unsigned char>& temp,
                         KeptBuffers& out) const {
    const std::uint32_t n = m_world.numParticles();
    const Stream& s = m_ctx;
    std::uint32_t* at = out.offsets.grow(std::size_t(n) + 1);
    Exec::forEach(s, std::uint64_t(n) + 1, TakenCountFn<KeyOf, Take>{rows, n, count.grow(std::size_t(n) + 1)},
                  "takenCount");
    Exec::exclusiveSum(s, temp, count.data(), at, n + 1);
    std::uint32_t total = 0;
    Exec::copyToHost(s, &total, at + n, 1);
    s.synchronize();
    Exec::forEach(s, n, TakeRowFn<KeyOf, Take>{rows, at, out.key.grow(total), out.hist.grow(total)}, "takeRow");
    return total;
  }

  // As CpuPipeline::keepHistory/keepMeshHistory: every non-zero ξ of a list, kept for the rebuild.
  void keepHistory() { takeRows(partnerRows(TakeAll{}), m_count, m_temp, m_kept); }
  void keepMeshHistory() { takeRows(meshRows(), m_count, m_temp, m_meshKept); }

  // As CpuPipeline::restoreHistory/restoreMeshHistory: each row of the new list takes its kept ξ.
  template <class KeyOf>
  void restoreRows(const KeptBuffers& kept, const std::uint32_t* offsets, KeyOf keyOf, Vec3f* hist) {
    Exec::forEach(m_ctx, m_world.numParticles(), RestoreRowFn<KeyOf>{kept.view(), m_orig.data(), offsets, keyOf, hist},
                  "restoreRow");
  }
  void restoreHistory() {
    restoreRows(m_kept, m_candOffsets.data(), PartnerKey{m_orig.data(), m_cand.data()}, m_hist.grow(m_numCand));
  }
  void restoreMeshHistory() {
    restoreRows(m_meshKept, m_meshOffsets.data(), TriangleKey{m_meshTri.data()}, m_meshHist.grow(m_numMeshCand));
  }

  // As CpuPipeline::readRows: the entries of `rows` with a non-zero ξ that rows.take accepts,
  // as make(scene index, key, ξ), sorted by (scene index, key); taken out of the list's rows
  // (count → scan → fill by scene index), or before the first rebuild from the kept ones.
  template <class Out, class KeyOf, class Take, class Make>
  std::vector<Out> readRows(const KeptBuffers& kept, const ListRows<KeyOf, Take>& rows, const Make& make) const {
    const std::uint32_t n = m_world.numParticles();
    const Stream& s = m_ctx;
    std::vector<std::uint32_t> at(std::size_t(n) + 1);
    std::vector<std::uint32_t> key;
    std::vector<Vec3f> hist;
    const KeptBuffers* from = &kept;
    if (m_listBuilt) {
      takeRows(rows, m_read.count, m_read.temp, m_read.out);
      from = &m_read.out;
    }
    from->offsets.download(at.data(), at.size(), s);
    s.synchronize();
    key.resize(at[n]);
    hist.resize(at[n]);
    from->key.download(key.data(), key.size(), s);
    from->hist.download(hist.data(), hist.size(), s);
    s.synchronize();
    return tumble::detail::readRows<Out>(n, at.data(), key.data(), hist.data(), rows.take, make);
  }

  // As CpuPipeline::reorder.
  void reorder() {
    const std::uint32_t nb = m_world.numBodies(), n = m_world.numParticles();
    if (nb < 2) return;
    const Stream& s = m_ctx;
    const std::uint32_t numChunks = (nb + exec::kBlock - 1) / exec::kBlock;
    Exec::reduceChunks(s, nb, exec::kBlock, BodyBoundsOp{m_bodies.data()}, m_boundsPart.grow(numChunks), "bodyBounds");
    m_hostBounds.resize(numChunks);
    m_boundsPart.download(m_hostBounds.data(), numChunks, s);
    s.synchronize();
    const MortonGrid g = tumble::detail::mortonGridOf(tumble::detail::combineBounds(m_hostBounds.data(), numChunks));
    std::uint32_t* keys = m_mKeys.grow(nb);
    std::uint32_t* vals = m_mVals.grow(nb);
    std::uint32_t* skeys = m_mSortedKeys.grow(nb);
    std::uint32_t* perm = m_perm.grow(nb);
    Exec::forEach(s, nb, MortonKeyFn{m_bodies.data(), g, keys, vals}, "mortonKey");
    Exec::radixSortPairs(s, m_temp, keys, skeys, vals, perm, nb, 0, 30);
    std::uint32_t* count = m_count.grow(std::size_t(nb) + 1);
    std::uint32_t* first = m_first.grow(std::size_t(nb) + 1);
    Exec::forEach(s, std::uint64_t(nb) + 1, PermutedCountFn{m_bodies.data(), perm, nb, count}, "permutedCount");
    Exec::exclusiveSum(s, m_temp, count, first, nb + 1);
    const bool springs = m_numSprings > 0, damping = m_numPlanes > 1;
    const ReorderColumns from{m_own.data(),  m_radius.data(), m_mass.data(),
                              m_hasMaterial ? m_material.data() : nullptr,
                              m_orig.data(), m_bodyOf.data(), springs ? m_tx.data() : nullptr,
                              springs ? m_ty.data() : nullptr, damping ? m_planeDamping.data() : nullptr};
    const ReorderColumns to{m_ownTmp.grow(n),  m_radiusTmp.grow(n), m_massTmp.grow(n),
                            m_hasMaterial ? m_materialTmp.grow(n) : nullptr, m_origTmp.grow(n),
                            m_bodyOfTmp.grow(n), springs ? m_txTmp.grow(m_numSprings) : nullptr,
                            springs ? m_tyTmp.grow(m_numSprings) : nullptr,
                            damping ? m_planeDampingTmp.grow(std::size_t(m_numPlanes - 1) * n) : nullptr};
    Exec::forEach(s, nb,
                  MoveBodiesFn{m_bodies.data(), m_bodyStatic.data(), perm, first, n, m_numPlanes, from,
                               m_bodiesNext.data(), m_bodyStaticTmp.grow(nb), to},
                  "moveBodies");
    std::swap(m_bodies, m_bodiesNext);
    std::swap(m_bodyStatic, m_bodyStaticTmp);
    std::swap(m_own, m_ownTmp);
    std::swap(m_radius, m_radiusTmp);
    std::swap(m_mass, m_massTmp);
    std::swap(m_orig, m_origTmp);
    std::swap(m_bodyOf, m_bodyOfTmp);
    if (m_hasMaterial) std::swap(m_material, m_materialTmp);
    if (springs) {
      std::swap(m_tx, m_txTmp);
      std::swap(m_ty, m_tyTmp);
    }
    if (damping) std::swap(m_planeDamping, m_planeDampingTmp);
  }

  Backend m_backend;
  Stream m_ctx;
  typename Exec::Timer m_timer;
  bool m_reorder = true;
  World m_world;
  LocalFrame m_frame;
  bool m_loaded = false;
  bool m_clumps = false;
  std::vector<Wall> m_planesNow;  // the planes (kernelWalls); with moving walls, setWallMotion's scratch
  std::uint32_t m_numPlanes = 0;  // the ground, then the walls
  bool m_wallsMove = false;       // some wall's surface moves: each step reads its own (stepBatch())
  std::size_t m_numSprings = 0;   // plane springs m_tx, m_ty: numPlanes × n, plane-major (or none)
  ContactLaw m_law = ContactLaw::Report;
  bool m_history = false;      // the law keeps a tangential history per contact
  bool m_listBuilt = false;    // a candidate list (and m_hist) exists since the load
  bool m_hasMaterial = false;  // hertz-mindlin with several materials: m_material (n)
  Buffer<std::uint16_t> m_material, m_materialTmp;
  Buffer<HertzPair> m_hertz, m_planeHertz;  // World::materialPairs, planeHertz
  // Internal numbering (see cpu/src/cpu_pipeline.cpp).
  Buffer<BodyRow> m_bodies, m_bodiesNext;
  Buffer<BodyStatic> m_bodyStatic;
  Buffer<OwnRow> m_own;
  Buffer<Wall> m_planes;
  Buffer<float> m_planeDamping, m_planeDampingTmp;  // planes 1.. (World::planeDamping), internal numbering
  Buffer<float> m_radius, m_mass, m_tx, m_ty;
  Buffer<std::uint32_t> m_orig, m_bodyOf;
  Buffer<PosRow> m_pos[2], m_buildPos;
  int m_cur = 0;
  Buffer<std::uint32_t> m_candOffsets, m_cand, m_candKey;
  Buffer<std::uint8_t> m_touching;  // the last step's contacts per particle (capped at 255)
  Buffer<Vec3f> m_hist;             // laws with a history: ξ per candidate-list entry
  KeptBuffers m_kept, m_meshKept;  // the contacts' ξ, the mesh springs
  // Mesh walls (kernelMesh()): their data on the device, the mesh candidate list with its springs
  // (as the CPU pipeline's), the poses of the moving meshes at the step's start (plane-indexed;
  // empty when no mesh moves) and their motion's bound for the skin test.
  struct MeshBuffers {
    Buffer<Vec3f> vertices;
    Buffer<std::uint32_t> triangles, triEdges, edgeTriOffsets, edgeTris, vertexTriOffsets, vertexTris, prims;
    Buffer<MeshTriangle> tri;
    Buffer<MeshBvhNode> nodes;
    std::uint32_t count = 0;
    std::uint32_t numTriangles() const { return count; }
    void upload(const KernelMesh& m, const Stream& s) {
      vertices.upload(m.vertices, s);
      triangles.upload(m.triangles, s);
      tri.upload(m.tri, s);
      triEdges.upload(m.triEdges, s);
      edgeTriOffsets.upload(m.edgeTriOffsets, s);
      edgeTris.upload(m.edgeTris, s);
      vertexTriOffsets.upload(m.vertexTriOffsets, s);
      vertexTris.upload(m.vertexTris, s);
      nodes.upload(m.nodes, s);
      prims.upload(m.prims, s);
      count = m.numTriangles();
    }
  };
  MeshBuffers m_mesh;
  bool hasMesh() const { return m_mesh.numTriangles() > 0; }
  Buffer<std::uint32_t> m_meshOffsets, m_meshTri;
  Buffer<Vec3f> m_meshHist;
  std::uint32_t m_numMeshCand = 0;
  std::uint32_t m_numPoses = 0;  // mesh poses per step: one per plane where a mesh moves, else none
  MeshMotionBound m_meshMotion;
  double m_rebuildTime = 0.0;  // the time of the last rebuild (the meshes' motion since)
  // readRows()'s scratch (a read-out allocates nothing once they have grown; the reads of a
  // state are const, its scratch is not).
  struct ReadScratch {
    Buffer<std::uint32_t> count;
    Buffer<unsigned char> temp;
    KeptBuffers out;
  };
  mutable ReadScratch m_read;
  // The hooks' scratch (readMotion(), writeMotion(), contactsOf()).
  struct HaloScratch {
    Buffer<std::uint32_t> at, list;
    Buffer<BodyMotion> motion;
    Buffer<unsigned long long> total;
  };
  mutable HaloScratch m_halo;
  std::uint32_t m_numCand = 0;
  float m_skin = 0.0f, m_skinLimit = 0.0f;
  bool m_needRebuild = true;
  // A batch of steps (stepBatch()): per step its read-back, and the host arrays its copies read.
  static constexpr std::uint32_t kMaxBatch = 64;
  Buffer<StepReadback> m_readback;
  std::vector<StepReadback> m_readbackInit, m_readbackHost;
  Buffer<std::uint32_t> m_stop;
  Buffer<double> m_meshClosure;
  std::vector<double> m_batchTimes, m_batchMeshes;
  std::vector<Wall> m_batchWalls;  // moving walls: each step's walls and mesh poses, step-major
  std::vector<MeshPose> m_batchPoses;
  Buffer<Wall> m_batchWallsDev;
  Buffer<MeshPose> m_batchPosesDev;
  const Wall* m_wallsAt = nullptr;        // the walls the next (or last) step reads
  const MeshPose* m_posesAt = nullptr;    // its mesh poses (moving meshes only)
  std::uint32_t m_batch = 8;  // the next batch's length: halved to the steps a rebuild allowed, doubled after a full one
  Broadphase<Exec> m_bp;
  PeriodicBox m_periodic;          // kernelPeriodic(); axes = 0: none
  float m_periodicGrowth = 0.0f;   // what the detection grows the radii by beyond skin/2 (periodicGrowth())
  PeriodicImages<Exec> m_images;   // the periodic detection's particles and ghosts
  // Scratch (grow-only).
  Buffer<float> m_bx, m_by, m_bz, m_br;
  Buffer<std::uint32_t> m_count, m_first, m_mKeys, m_mVals, m_mSortedKeys, m_perm;
  Buffer<tumble::detail::BoundsPartial> m_boundsPart;
  std::vector<tumble::detail::BoundsPartial> m_hostBounds;
  Buffer<unsigned char> m_temp;
  Buffer<BodyStatic> m_bodyStaticTmp;
  Buffer<OwnRow> m_ownTmp;
  Buffer<float> m_radiusTmp, m_massTmp, m_txTmp, m_tyTmp;
  Buffer<std::uint32_t> m_origTmp, m_bodyOfTmp;
  Buffer<float> m_dbg[5], m_dbgVel;
  StepStats m_stats;
  std::uint32_t m_pulls = 0;
  double m_time = 0.0;
  std::uint64_t m_steps = 0;
  bool m_debug = false;
  bool m_hasDebug = false;
};

}  // namespace TUMBLE_EXEC_ABI
}  // namespace tumble::gpu::detail
