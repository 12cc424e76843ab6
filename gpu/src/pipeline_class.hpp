// SPDX-License-Identifier: MIT
// The CUDA pipeline's class, CudaPipeline<Exec> (design notes in pipeline.hpp): its state, the
// Pipeline interface's short members, load(), and the steps: step(), stepBatch() and the
// launches of the step's functors. Its other members are defined out of line by stage, in
// pipeline_rebuild.hpp (the rebuild: lists, reordering, the histories across it) and
// pipeline_readout.hpp (the read-outs, the hooks of a domain decomposition, findPairs()); the
// functors it launches are in pipeline_step_fns.hpp, pipeline_list_fns.hpp,
// pipeline_reorder_fns.hpp and pipeline_readout_fns.hpp. Internal to tumble::gpu: include
// pipeline.hpp, which holds every part.
#pragma once
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "broadphase.hpp"
#include "periodic_images.hpp"
#include "pipeline_list_fns.hpp"
#include "pipeline_readout_fns.hpp"
#include "pipeline_reorder_fns.hpp"
#include "pipeline_step_fns.hpp"
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
    m_hasFlows = false;
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
    m_neck = neckReach(w);
    // Periodic boundaries (periodic_images.hpp), as CpuPipeline::load.
    m_periodic = kernelPeriodic(w.params, m_frame);
    m_periodicGrowth = m_periodic.axes != 0 ? periodicGrowth(w.maxRadius + 0.5f * (m_skin + m_neck), m_periodic) : 0.0f;
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

  // The read-outs and the hooks of a domain decomposition (pipeline_readout.hpp).
  void readLocalState(BodyState& out) const override;
  void readLocalPositions(std::vector<float>& out) const override;
  std::vector<Pair> pairs() const override;
  std::vector<MeshContact> meshContacts() const override;
  void readMotion(const std::vector<std::uint32_t>& bodies, std::vector<BodyMotion>& out) const override;
  void writeMotion(const std::vector<std::uint32_t>& bodies, const std::vector<BodyMotion>& motion) override;
  std::uint64_t contactsOf(const std::vector<std::uint32_t>& bodies) const override;
  bool contactSumsPerBody(const SpringLaw& law, std::vector<ContactSums>& out) const override;
  std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) override;

  void setDebugCapture(bool on) override { m_debug = on; }
  void readDebug(ParticleDebug& out) const override;
  void setEnergyTally(bool on) override { m_tallyOn = on; }
  EnergyLimbs energyOf(const std::vector<std::uint32_t>& bodies) const override;

  // A pull along a periodic axis is left off (its potential has no period; scene files refuse it).
  void setPulls(std::uint32_t mask) override { m_pulls = mask & 7u & ~m_world.params.periodic.conflictingPulls(); }
  std::uint32_t pulls() const override { return m_pulls; }
  const StepStats& stats() const override { return m_stats; }
  void resetStats() override {
    m_stats = StepStats{};
    m_stats.skin = m_skin;
    m_tally.clear();
  }
  double time() const override { return m_time; }
  std::uint64_t stepCount() const override { return m_world.step + m_steps; }

 private:
  // The candidate list of the last step as the readouts of its contacts see it (pairs(), the
  // counts, the guard's sums): under JKR with the entries' springs (CandidateListView::held).
  CandidateListView readoutList() const {
    CandidateListView l = compactList(m_candOffsets.data(), m_cand.data());
    if (m_world.params.contact.cohesion == Cohesion::Jkr) l.held = m_hist.data();
    return l;
  }
  // The contacts of a list as sorted pairs (pairs(), findPairs()), and findPairs() with periodic
  // boundaries (pipeline_readout.hpp).
  std::vector<Pair> contactsOf(const PosRow* pos, const std::uint32_t* orig, const CandidateListView& list,
                               const std::uint8_t* touching, const PeriodicBox& box, std::uint32_t n) const;
  std::vector<Pair> findPeriodicPairs(const ParticleCloud& cloud, const BroadphaseInput& in, const BroadphaseParams& bp,
                                      Broadphase<Exec>& b);

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
                    nullptr,   // the list's rows are walked one by one (no owners)
                    nullptr};  // the list is the candidate list: ξ of entry e at history[e]
  }

  // As CpuPipeline::stepOnce, `count` times in a row with no host round trip between the steps:
  // each step's kernel, then its skin test on the device (DecideFn). Where a step's test asks for
  // a rebuild, the batch's later steps do nothing, and the host, which reads the batch's outcome
  // once at its end, rebuilds before the next step. Returns the steps taken (at least 1).
  std::uint32_t stepBatch(std::uint32_t count) {
    const std::uint32_t n = m_world.numParticles(), nb = m_world.numBodies();
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
    DebugForcesView dbg{{nullptr, nullptr, nullptr, nullptr, nullptr}, nullptr, nullptr};
    if (m_debug) {
      for (int k = 0; k < 5; ++k) dbg.f[k] = m_dbg[k].grow(3 * std::size_t(n));
      dbg.v = m_dbgVel.grow(3 * std::size_t(n));
      dbg.contact = m_dbgContact.grow(m_numCand);  // an entry each of the candidate list
    }
    // The energy tally: each step's flows per body (the debug pass, without its capture
    // unless m_debug), summed per step of the batch.
    EnergyFlows* flows = m_tallyOn ? m_bodyFlows.grow(nb) : nullptr;
    EnergyLimbs* energy = nullptr;
    if (m_tallyOn) {
      energy = m_energy.grow(count);
      Exec::fillZero(s, energy, count);
    }
    for (std::uint32_t k = 0; k < count; ++k) {
      if (m_wallsMove) setWallsOfStep(k);
      StepView v = stepView();
      v.bodyFlows = flows;
      m_debug || m_tallyOn ? launchStep<true>(v, fp, dbg, rb + k, stop) : launchStep<false>(v, fp, dbg, rb + k, stop);
      if (m_tallyOn)
        Exec::forEach(s, (nb + kTallyRun - 1) / kTallyRun, TallyFn{flows, nb, p.dt, stop, energy + k}, "tally");
      Exec::forEach(s, 1, DecideFn{rb, m_meshClosure.data(), k, m_skinLimit, hasMesh(), stop}, "decide");
      m_cur = 1 - m_cur;  // as if the step is taken; corrected below for the steps that were not
      std::swap(m_bodies, m_bodiesNext);
    }
    m_timer.mark(Phase::Integrate, s);  // in the forces' kernel: no time of its own, as on the CPU

    std::uint32_t stopped = 0;
    Exec::copyToHost(s, &stopped, stop, 1);
    m_readbackHost.resize(count);
    Exec::copyToHost(s, m_readbackHost.data(), rb, count);
    if (m_tallyOn) {
      m_energyHost.resize(count);
      Exec::copyToHost(s, m_energyHost.data(), energy, count);
    }
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
    m_hasFlows = m_tallyOn;
    if (m_tallyOn) {
      for (std::uint32_t k = 0; k < taken; ++k) m_tally.add(m_energyHost[k]);
      m_stats.energy = m_tally.joules();
    }
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

  // The rebuild: the lists, the reordering and the histories across it (pipeline_rebuild.hpp).
  void rebuild();
  template <bool kPosed>
  void buildMeshList();
  void reorder();

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

  // The histories across a rebuild and their read-out (pipeline_rebuild.hpp).
  template <class KeyOf, class Take>
  std::uint32_t takeRows(const ListRows<KeyOf, Take>& rows, Buffer<std::uint32_t>& count, Buffer<unsigned char>& temp,
                         KeptBuffers& out) const;
  void keepHistory();
  void keepMeshHistory();
  template <class KeyOf>
  void restoreRows(const KeptBuffers& kept, const std::uint32_t* offsets, KeyOf keyOf, Vec3f* hist);
  void restoreHistory();
  void restoreMeshHistory();
  template <class Out, class KeyOf, class Take, class Make>
  std::vector<Out> readRows(const KeptBuffers& kept, const ListRows<KeyOf, Take>& rows, const Make& make) const;

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
  float m_neck = 0.0f;  ///< neckReach(): the detection reaches this far beyond the skin
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
  Buffer<ContactForce> m_dbgContact;
  StepStats m_stats;
  std::uint32_t m_pulls = 0;
  double m_time = 0.0;
  std::uint64_t m_steps = 0;
  bool m_debug = false;
  bool m_hasDebug = false;
  // The energy tally (as CpuPipeline's): the last step's flows per body, each step's sums of a
  // batch, the sum since load() or resetStats() (m_stats.energy: in joules).
  bool m_tallyOn = false;
  bool m_hasFlows = false;
  Buffer<EnergyFlows> m_bodyFlows;
  Buffer<EnergyLimbs> m_energy;
  std::vector<EnergyLimbs> m_energyHost;
  mutable std::vector<EnergyFlows> m_flowsHost;
  mutable std::vector<std::uint32_t> m_atHost;
  EnergyTally m_tally;
};

}  // namespace TUMBLE_EXEC_ABI
}  // namespace tumble::gpu::detail
