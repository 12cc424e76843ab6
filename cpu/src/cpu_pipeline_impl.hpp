// SPDX-License-Identifier: MIT
// The CPU reference pipeline's class (internal to tumble_cpu), its members defined by stage in
// cpu_pipeline.cpp (the Pipeline interface: load, read-backs, halo exchange; design notes there),
// cpu_pipeline_step.cpp (one step: the list decision and the per-body pass), cpu_pipeline_lists.cpp
// (the rebuilds: detection, candidate, near and mesh lists, reordering) and
// cpu_pipeline_history.cpp (the contact histories kept across a rebuild).
#pragma once
#include "tumble/cpu/cpu_pipeline.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cfloat>
#include <string>

#include "tumble/cpu/broadphase.hpp"
#include "grow.hpp"
#include "periodic_images.hpp"
#include "tumble/cpu/radix_sort.hpp"
#include "tumble/cpu/scan.hpp"
#include "tumble/cpu/threads.hpp"
#include "tumble/error.hpp"
#include "tumble/guard.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/history.hpp"
#include "tumble/kernels/step.hpp"
#include "tumble/mesh.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble::cpu::impl {

using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
inline constexpr std::uint32_t kGrain = 2048;      // particles per task
inline constexpr std::uint32_t kBodyGrain = 256;   // bodies per task of the step pass
inline constexpr float kNearSkinFraction = 0.25f;  // near skin / skin: chosen by measurement (docs/performance.md)

template <class F>
void forEach(std::uint32_t n, std::uint32_t grain, F&& f) {
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, grain), [&](const auto& rg) {
    for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) f(i);
  });
}

/// The per-step reduction: the drift since the rebuild (skin test) and the touching contacts.
struct StepTotals {
  Drift drift = noDrift();
  std::uint64_t contacts = 0;
};

class CpuPipeline final : public HaloPipeline {
 public:
  explicit CpuPipeline(const PipelineOptions& o)
      : m_allowThreads(allowThreads(o.threads)),
        m_arena(o.threads > 0 ? o.threads : tbb::task_arena::automatic),
        m_reorder(o.reorder) {}

  Backend backend() const override { return Backend::Cpu; }

  void load(const World& world) override;

  void step(std::uint64_t n) override;

  void readState(BodyState& out) const override;
  LocalFrame frame() const override { return m_frame; }

  void readLocalState(BodyState& out) const override;

  void readLocalPositions(std::vector<float>& out) const override;

  std::vector<Pair> pairs() const override;

  std::vector<MeshContact> meshContacts() const override;

  bool contactSumsPerBody(const SpringLaw& law, std::vector<ContactSums>& out) const override;

  std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) override;

  void setDebugCapture(bool on) override { m_debug = on; }

  void setEnergyTally(bool on) override { m_tallyOn = on; }

  void readDebug(ParticleDebug& out) const override;

  // A pull along a periodic axis is left off (its potential has no period; scene files refuse it).
  void setPulls(std::uint32_t mask) override { m_pulls = mask & 7u & ~m_world.params.periodic.conflictingPulls(); }
  std::uint32_t pulls() const override { return m_pulls; }
  const StepStats& stats() const override { return m_stats; }
  void resetStats() override;
  double time() const override { return m_time; }
  std::uint64_t stepCount() const override { return m_world.step + m_steps; }

  void readMotion(const std::vector<std::uint32_t>& bodies, std::vector<BodyMotion>& out) const override;

  void writeMotion(const std::vector<std::uint32_t>& bodies, const std::vector<BodyMotion>& motion) override;

  std::uint64_t contactsOf(const std::vector<std::uint32_t>& bodies) const override;

  EnergyLimbs energyOf(const std::vector<std::uint32_t>& bodies) const override;

  std::vector<TrafficLine> stepTraffic() const override;

 private:
  const std::vector<std::uint32_t>& internalBodies() const;

  void decideList(const Drift& drift, double next);

  void stepOnce();
  void tallyStep();

  // How far the particles may have closed in under a drift: on each other (closureOf()), and
  // with mesh walls on a static wall too (wallClosureOf(), which is at least that).
  float closureFor(const Drift& d) const { return m_hasMesh ? wallClosureOf(d) : closureOf(d); }

  template <bool kDebug>
  StepTotals advanceAs();
  template <bool kDebug, bool kPeriodic, bool kPosedMesh>
  StepTotals advanceLaw();

  template <bool kDebug, bool kClumps, ContactLaw kLaw, bool kPeriodic, bool kPosedMesh>
  StepTotals advance();

  void rebuild();

  void refreshNear();

  void setBodyReference();

  template <bool kPeriodic>
  Drift driftSinceRebuild();

  void fillNearList();

  void ownRow(const std::vector<std::uint32_t>& offsets, std::uint32_t i);

  CandidateListView contactListView() const;

  void computePositions();

  void buildList();

  void buildPeriodicList(const SweepListView& s);

  std::vector<Pair> findPeriodicPairs(const ParticleCloud& cloud, const BroadphaseInput& in, const BroadphaseParams& bp,
                                      cpu::detail::Broadphase& b);

  // Histories across a rebuild (the contact histories of laws with a history, the mesh
  // springs). Before it, the non-zero ξ of a list are kept per particle by scene index, each
  // with its key (the partner's scene index, or the triangle), in the row's order (ascending
  // key); after it, each row of the new list takes the ξ of its keys there, by a merge of the
  // two sorted rows, and zero for the others. So the history depends on the contacts only, not
  // on the list, the skin or the numbering.
  struct KeptHistories : tumble::detail::KeptRows {
    std::vector<std::uint32_t> count;  // scratch
  };

  template <class KeyOf>
  void keepRows(const std::vector<std::uint32_t>& offsets, const std::vector<Vec3f>& hist, const KeyOf& keyOf,
                KeptHistories& out);

  template <class KeyOf>
  void restoreRows(const KeptHistories& kept, const std::vector<std::uint32_t>& offsets, const KeyOf& keyOf,
                   std::vector<Vec3f>& hist);

  template <class Out, class KeyOf, class Take, class Make>
  std::vector<Out> readRows(const KeptHistories& kept, const std::vector<std::uint32_t>& offsets,
                            const std::vector<Vec3f>& hist, const KeyOf& keyOf, const Take& take, const Make& make) const;

  void keepHistory();
  void restoreHistory();

  void keepLoadedHistory(const std::vector<ContactHistory>& contacts);

  void readHistory(std::vector<ContactHistory>& out) const;

  void keepMeshHistory();
  void restoreMeshHistory();
  void keepLoadedMeshHistory(const std::vector<MeshContactHistory>& contacts);
  void readMeshHistory(std::vector<MeshContactHistory>& out) const;

  void buildMeshList();
  template <bool kPosed>
  void buildMeshRows();

  void scanCounts(const std::uint32_t* count, std::size_t len, std::uint32_t* out);

  void reorder();

  StepView stepView();

  std::unique_ptr<tbb::global_control> m_allowThreads;  // before the arena: --threads above the cores
  mutable tbb::task_arena m_arena;
  bool m_reorder = true;
  World m_world;  // in the integration frame; static tables in scene order
  LocalFrame m_frame;
  bool m_clumps = false;
  std::vector<Wall> m_planes;     // the ground, then the walls (kernelWalls())
  bool m_wallsMove = false;            // some wall's surface moves (setWallMotion() before each step)
  std::vector<float> m_planeDamping;   // planes 1.. (World::planeDamping), internal numbering
  std::vector<HertzPair> m_planeHertz;
  ContactLaw m_law = ContactLaw::Report;
  PeriodicBox m_periodic;   // periodic boundaries in the integration frame (axes 0: none)
  float m_periodicGrowth = 0.0f;  // what the detection grows the radii by beyond skin/2 (periodicGrowth())
  cpu::detail::PeriodicImages m_images;  // the periodic detection's particles and ghosts
  bool m_history = false;   // the law keeps a tangential history per contact
  bool m_listBuilt = false; // a candidate list (and m_hist) exists since the load

  // Internal numbering (see the design notes).
  std::vector<BodyRow> m_bodies, m_bodiesNext;  // double-buffered: neighbours read this step's
  std::vector<BodyStatic> m_bodyStatic;
  std::vector<OwnRow> m_own;
  std::vector<float> m_radius, m_mass;
  std::vector<std::uint16_t> m_material;  // hertz-mindlin with several materials; else empty
  std::vector<std::uint32_t> m_orig;   // scene index of each particle
  std::vector<std::uint32_t> m_bodyOf; // body of each particle (the sweep skips same-body pairs)
  std::vector<float> m_gtx, m_gty;     // plane springs, plane-major (empty without planes)
  std::vector<PosRow> m_pos[2];        // particle rows, double-buffered: [m_cur] is this step's
  int m_cur = 0;
  bool m_perBody = false;            // the skin test per body (bodyDrift()), else per particle
  std::vector<BodyRef> m_bodyRef;    // the reference of the skin test per body: the bodies at the last refresh
  std::vector<PosRow> m_buildPos;    // that of the test per particle: their positions then
  std::vector<PosRow> m_rebuildPos;  // positions at the last rebuild
  std::vector<std::uint32_t> m_candOffsets, m_cand;
  std::vector<std::uint8_t> m_touching;  // the last step's contacts per particle (capped at 255)
  std::vector<Vec3f> m_hist;             // laws with a history: ξ per candidate-list entry
  // The histories kept across a rebuild (or from the load): CSR by scene index (keepHistory).
  KeptHistories m_keep, m_meshKeep;
  // Mesh walls: their kernels' data (in the integration frame) and the mesh candidate list,
  // rows by internal particle at m_meshOffsets, with the springs ξ per entry (buildMeshList()).
  KernelMesh m_mesh;
  bool m_hasMesh = false;
  // Moving meshes: their poses at the step's start (plane-indexed; empty when no mesh moves), the
  // bound on their motion for the skin test, and the time of the last rebuild.
  std::vector<MeshPose> m_meshPoses;
  MeshMotionBound m_meshMotion;
  double m_rebuildTime = 0.0;
  std::vector<std::uint32_t> m_meshOffsets, m_meshTri;
  std::vector<Vec3f> m_meshHist;
  float m_skin = 0.0f;
  float m_neck = 0.0f;  // neckReach(): detection and the near list reach this far beyond the skin
  bool m_needRebuild = true;
  // The near list (kernels/contact_list.hpp fillNear), compact; under a law with history the
  // candidate entry of each of its entries, where its ξ is (StepView::historySlot).
  std::vector<std::uint32_t> m_nearOffsets, m_near, m_nearRoom, m_nearSlot, m_nearSlotRoom;
  std::vector<std::uint32_t> m_owner;  // the particle of each entry of contactListView() (StepView::listOwner)
  float m_nearSkin = 0.0f;     // 0: no near list
  float m_fullLimit = 0.0f;    // the candidate list holds while m_closed + closure < this
  float m_nearLimit = 0.0f;    // the near list holds while its interval's closure < this
  double m_closed = 0.0;       // bound on the closure from the rebuild to the last refresh
  float m_lastClosure = 0.0f;  // closure of the current interval after the last step
  bool m_needRefresh = false;

  cpu::detail::Broadphase m_bp;
  // Scratch (grow-only).
  std::vector<float> m_bx, m_by, m_bz, m_br;
  std::vector<std::uint32_t> m_count, m_candKey, m_first;
  std::vector<std::uint32_t> m_roomOffsets, m_roomCand;  // buildPeriodicList(): rows before compaction
  std::vector<std::uint32_t> m_mKeys, m_mVals, m_mSortedKeys, m_perm;
  std::vector<std::byte> m_temp;
  std::vector<BodyStatic> m_bodyStaticTmp;
  std::vector<OwnRow> m_ownTmp;
  std::vector<float> m_radiusTmp, m_massTmp, m_gtxTmp, m_gtyTmp, m_planeDampingTmp;
  std::vector<std::uint16_t> m_materialTmp;
  std::vector<std::uint32_t> m_origTmp, m_bodyOfTmp;
  std::vector<float> m_dbg[5], m_dbgVel;
  std::vector<ContactForce> m_dbgContact;  // per entry of contactListView() (debug capture)
  struct PairChunk {
    std::vector<std::uint32_t> i, j;
  };
  mutable std::vector<PairChunk> m_pairChunks;  // pairs() scratch
  mutable std::vector<std::uint32_t> m_pairI, m_pairJ, m_pairSortedI, m_pairSortedJ;
  mutable std::vector<std::byte> m_pairTemp;
  mutable std::vector<std::uint32_t> m_internal;  // internalBodies() scratch

  StepStats m_stats;
  std::uint32_t m_pulls = 0;
  double m_time = 0.0;
  std::uint64_t m_steps = 0;
  bool m_debug = false;
  bool m_hasDebug = false;
  // The energy tally: on, the last step's flows per body (internal numbering; m_hasFlows),
  // the sum since load() or resetStats() (m_stats.energy: in joules).
  bool m_tallyOn = false;
  bool m_hasFlows = false;
  std::vector<EnergyFlows> m_bodyFlows;
  EnergyTally m_tally;
};

}  // namespace tumble::cpu::impl
